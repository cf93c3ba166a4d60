#ifndef PARKSLAM_PERCEPTION_LEARNED_SLOT_DETECTOR_H_
#define PARKSLAM_PERCEPTION_LEARNED_SLOT_DETECTOR_H_

// Learned parking-slot detection in the top view (paper III-A: "marking
// points are detected by a CNN", as DMPR-PS does): a small fully
// convolutional network (scripts/learned/models.py, MarkingPointNet) looks
// at the top view resized to input_size_px and predicts, per cell of a grid
// 16 times coarser, the confidence that a marking point lies in the cell,
// its place in the cell, the direction of its separating line and its
// shape (T or L). Cells above min_confidence become marking points, the
// weaker of two within nms_radius_px is dropped, and slots are formed from
// the points by the paper's rules (slot_pairing.h). The network sees no
// lines, so the slots are then checked on the paint (slot_paint_check.h):
// a candidate with another separating line across it is split at that
// line's missed point, a row is extended by the corners its slots lead
// to, each slot's corners are moved onto the painted lines' centres, and
// parallel slots whose lines leave the view at once, and slots at the
// border whose width is not their row's, are dropped (slot_pairing.h).
//
// Top-view pixels are 0-based, (0, 0) the centre of the top-left pixel,
// x to the right and y down (camera/top_view.h).

#include <memory>
#include <string>

#include <opencv2/core.hpp>

#include "parkslam/perception/onnx_network.h"
#include "parkslam/perception/slot_detector.h"
#include "parkslam/perception/slot_paint_check.h"
#include "parkslam/perception/slot_pairing.h"

namespace parkslam::perception {

// The scale the networks learned: 600 top-view pixels for 10 m (ps2.0).
inline constexpr double kLearnedPixelsPerM = 60.0;

// What the classical detector (slot_detector.h) does with the network's
// marking points: nothing; kRefine: a point the classical detector also
// found (within classical_match_px and classical_match_rad) takes its
// position and direction, measured on the painted lines; kFilter: as
// kRefine, and points it did not find are dropped.
enum class ClassicalCheck { kNone, kRefine, kFilter };

struct LearnedSlotDetectorOptions {
  // The exported network (models/marking_points.onnx in the source tree).
  std::string model_path;
  // Its input: the top view is resized to this square (the network was
  // trained at this size).
  int input_size_px = 256;
  // The threshold with the best F1 on the synthetic validation set
  // (models/marking_points.onnx.json, "validation").
  double min_confidence = 0.6;
  // A weaker point, of at least min_partner_confidence, is kept where it
  // makes a slot (every pairing rule) with a point of min_confidence or
  // more (0: none kept).
  double min_partner_confidence = 0.0;
  // A weaker point, of at least weak_point_min_confidence, is kept where
  // the paint shows its junction (slot_paint_check.h, MeasurePointPaint):
  // its separating line along the network's direction, within
  // weak_point_max_angle_rad, and an entrance line at a right angle to it
  // (0: none kept). With strong_points_need_paint, points of
  // min_confidence or more wholly in view without that junction go too.
  double weak_point_min_confidence = 0.0;
  double weak_point_max_angle_rad = 0.35;
  // Each line painted in at least this share of its cross-sections in view
  // (0: refine_min_sections of them suffice).
  double weak_point_min_painted_share = 0.0;
  bool strong_points_need_paint = false;
  // Test-time flips: the network also sees the view mirrored left-right
  // (2) or left-right, up-down and both (4), and the cells are averaged
  // after mirroring them back. 1: the view alone. Each flip costs one more
  // pass of the network.
  int flips = 1;
  // A point whose separating line leads towards the car (the image centre)
  // from more than this is dropped (0: none): its slot would open towards a
  // car beyond its far end, which the pairing rejects
  // (SlotPairingOptions::max_vehicle_depth_in_row_m). Such points are the
  // far ends of separating lines; on the synthetic validation set every one
  // is false.
  double max_point_depth_towards_car_m = 4.0;
  // Two marking points closer than this (top-view pixels) are one.
  double nms_radius_px = 20.0;
  // Points closer than this to the image's border are dropped: a junction
  // cut by the border shows too little of its arms to be placed (the
  // network puts it where its paint leaves the image).
  double border_margin_m = 0.0;
  SlotPairingOptions pairing;
  // The pairing checked on the paint (slot_paint_check.h): a candidate
  // with another separating line painted across its interior is removed,
  // and with recover_points that line's marking point, which the network
  // missed, is added where the line meets the entrance, and the points
  // are paired again.
  bool check_paint = true;
  bool recover_points = true;
  // Rows extended on the paint: next to each slot of a row (entrance
  // shorter than a parallel slot's), one slot width on along the entrance,
  // a separating line painted where the next corner should be adds that
  // corner, which the network missed (with check_paint).
  bool extend_rows = true;
  // The line found within this of the expected corner, along the entrance.
  double extend_tolerance_m = 0.3;
  SlotPaintCheckOptions paint_check;
  // The slots' entrance corners refined on the paint next to them
  // (slot_paint_check.h, RefineSlotCorners): the network's cells are 2.3
  // top-view pixels wide at 256 px. Their marking points move with them.
  bool refine_on_paint = true;
  ClassicalCheck classical = ClassicalCheck::kNone;
  SlotDetectorOptions classical_options;
  double classical_match_px = 10.0;
  double classical_match_rad = 0.5235987755982988;  // 30 degrees

  bool IsValid(std::string* error) const;

  // The field list, walked by the options file reader (io/options_yaml.h).
  // Not listed: classical (choices set on the command line).
  template <typename V>
  void VisitFields(V& v) {
    v("model_path", model_path);
    v("input_size_px", input_size_px);
    v("min_confidence", min_confidence);
    v("min_partner_confidence", min_partner_confidence);
    v("weak_point_min_confidence", weak_point_min_confidence);
    v("weak_point_max_angle_rad", weak_point_max_angle_rad);
    v("weak_point_min_painted_share", weak_point_min_painted_share);
    v("strong_points_need_paint", strong_points_need_paint);
    v("flips", flips);
    v("max_point_depth_towards_car_m", max_point_depth_towards_car_m);
    v("nms_radius_px", nms_radius_px);
    v("border_margin_m", border_margin_m);
    v("pairing", pairing);
    v("check_paint", check_paint);
    v("recover_points", recover_points);
    v("extend_rows", extend_rows);
    v("extend_tolerance_m", extend_tolerance_m);
    v("refine_on_paint", refine_on_paint);
    v("paint_check", paint_check);
    v("classical_options", classical_options);
    v("classical_match_px", classical_match_px);
    v("classical_match_rad", classical_match_rad);
  }
};

class LearnedSlotDetector {
 public:
  // Loads the network. Throws std::invalid_argument on invalid options and
  // std::runtime_error naming the file when the weights are missing or
  // unusable.
  explicit LearnedSlotDetector(const LearnedSlotDetectorOptions& options);

  // Detects marking points and slots in an 8-bit BGR (or grey) top view.
  // Marking points on pixels where mask is zero (the car's footprint) are
  // dropped; mask may be empty. SlotDetection::lines stays empty.
  SlotDetection Detect(const cv::Mat& top_view, const cv::Mat& mask = cv::Mat()) const;

  // The network's raw output for a top view: 6 x G x G floats (confidence,
  // offset x, offset y, cos, sin, T probability per cell).
  cv::Mat Cells(const cv::Mat& top_view) const;

  const LearnedSlotDetectorOptions& options() const { return options_; }

 private:
  // The paint check of options_.check_paint on the paired detection, in
  // the grey top view.
  void CheckOnPaint(const cv::Mat& grey, const cv::Mat& mask, SlotDetection* detection) const;
  // The corners options_.extend_rows finds next to the detected slots,
  // as marking points (direction and score of the slot they extend).
  std::vector<MarkingPoint> MissedRowCorners(const cv::Mat& grey, const cv::Mat& mask,
                                             const SlotDetection& detection) const;

  LearnedSlotDetectorOptions options_;
  std::unique_ptr<OnnxNetwork> network_;
  std::unique_ptr<SlotDetector> classical_;
  SlotPaintCheckOptions paint_check_;  // at the pairing's scale
};

}  // namespace parkslam::perception

#endif  // PARKSLAM_PERCEPTION_LEARNED_SLOT_DETECTOR_H_
