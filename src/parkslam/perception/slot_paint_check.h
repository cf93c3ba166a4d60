#ifndef PARKSLAM_PERCEPTION_SLOT_PAINT_CHECK_H_
#define PARKSLAM_PERCEPTION_SLOT_PAINT_CHECK_H_

// The paper's pairing rule on the paint (III-A: an entrance-line candidate
// with more than two marking points on it is removed) for detectors that
// find points but no lines. When a marking point is missed, its two
// neighbours pair across it into one slot two slots wide, or across the gap
// between two groups of slots; but the missed point's separating line still
// runs through that candidate's interior. The check looks for it.
//
// Cross-sections parallel to the entrance, at a few depths into the slot,
// are sampled from the grey top view. Painted line: a narrow stripe (of a
// line's width) brighter than the floor on both sides by a contrast; a
// separating line: such a stripe at the same place along the entrance in
// every cross-section, away from the slot's own two lines. Digits painted
// inside the slot are shorter than the span of the cross-sections, and a
// car's body is wider than a line.
//
// Top-view pixels are 0-based, x to the right and y down
// (camera/top_view.h).

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "parkslam/perception/slot_detector.h"

namespace parkslam::perception {

struct SlotPaintCheckOptions {
  double pixels_per_m = 60.0;  // 600 px for 10 m (ps2.0)
  // Cross-sections at first_depth_m, then every depth_step_m, depth_count
  // of them; those wholly in view are used, at least min_depths_in_view
  // (else the slot is kept as it is). A separating line crosses every one
  // in view. Painted IDs lie within the first metre of a slot: they may
  // cross the first cross-section, never the second.
  double first_depth_m = 0.45;
  double depth_step_m = 0.6;
  int depth_count = 3;
  int min_depths_in_view = 2;
  // A cross-section is in view when this share of it, between the slot's
  // own lines, is (off the image or on the car's footprint: not).
  double min_share_in_view = 0.7;
  // Stripes this close to either marking point along the entrance belong
  // to the slot's own separating lines.
  double end_margin_m = 0.35;
  // A painted line's width range.
  double min_line_width_m = 0.06;
  double max_line_width_m = 0.30;
  // A stripe stands above both sides by at least this many grey levels and
  // by own_line_share of the contrast of the slot's own separating lines.
  double min_contrast_grey = 20.0;
  double own_line_share = 0.5;
  // One line's stripes in successive cross-sections agree within this
  // along the entrance (the line may lean a few degrees off the slot's
  // depth direction).
  double max_drift_m = 0.1;
  // Refining a slot's entrance corners on the paint: cross-sections of its
  // separating line from refine_begin_m to refine_separating_end_m along
  // it, and of its entrance line from refine_begin_m to refine_end_m from
  // the corner towards the other one (an L's stub may be short), each
  // +-refine_half_window_m wide; a line is fitted through their centres
  // when at least refine_min_sections of them show paint.
  double refine_begin_m = 0.2;
  double refine_end_m = 0.6;
  double refine_separating_end_m = 1.2;
  double refine_half_window_m = 0.18;
  int refine_min_sections = 5;

  bool IsValid(std::string* error) const;

  // The field list, walked by the options file reader (io/options_yaml.h).
  template <typename V>
  void VisitFields(V& v) {
    v("pixels_per_m", pixels_per_m);
    v("first_depth_m", first_depth_m);
    v("depth_step_m", depth_step_m);
    v("depth_count", depth_count);
    v("min_depths_in_view", min_depths_in_view);
    v("min_share_in_view", min_share_in_view);
    v("end_margin_m", end_margin_m);
    v("min_line_width_m", min_line_width_m);
    v("max_line_width_m", max_line_width_m);
    v("min_contrast_grey", min_contrast_grey);
    v("own_line_share", own_line_share);
    v("max_drift_m", max_drift_m);
    v("refine_begin_m", refine_begin_m);
    v("refine_end_m", refine_end_m);
    v("refine_separating_end_m", refine_separating_end_m);
    v("refine_half_window_m", refine_half_window_m);
    v("refine_min_sections", refine_min_sections);
  }
};

// What the paint shows of a slot candidate (corners 0 and 1 its entrance,
// depth_dir_px into it) in an 8-bit grey top view. Pixels where mask is
// zero (the car's footprint), or black (unseen), count as out of view;
// mask may be empty.
struct SlotPaint {
  // Separating lines painted across the interior: where each meets the
  // entrance line, in pixels.
  std::vector<Eigen::Vector2d> lines_inside;
};
SlotPaint MeasureSlotPaint(const cv::Mat& grey, const cv::Mat& mask, const DetectedSlot& slot,
                           const SlotPaintCheckOptions& options);

// Corners a row leads to but no marking point marks: one slot width on
// past each entrance corner of each slot narrower than max_width_px, away
// from its other corner, where no known point lies within half a width, a
// separating line painted within tolerance_px of where the next corner
// should be (MeasureSlotPaint on a probe from the corner to a little past
// it). Each in the image, with the slot it extends.
struct RowCorner {
  Eigen::Vector2d px = Eigen::Vector2d::Zero();
  int slot = -1;  // index into the slots given
};
std::vector<RowCorner> FindRowCorners(const cv::Mat& grey, const cv::Mat& mask,
                                      const std::vector<DetectedSlot>& slots,
                                      const std::vector<Eigen::Vector2d>& known_px,
                                      double max_width_px, double tolerance_px,
                                      const SlotPaintCheckOptions& options);

// Moves a slot's entrance corners (0 and 1) to where the centrelines of
// their separating line and of the entrance line cross, each fitted to the
// paint next to the corner, turns the slot's depth direction to the mean of
// the fitted separating lines, and puts the far corners behind the
// entrance at the depth they had; a corner whose lines show too little
// paint stays. The detector's cells
// are coarser than the paint (a network's stride is several pixels), the
// lines' centres are not. Returns how many corners moved.
int RefineSlotCorners(const cv::Mat& grey, const cv::Mat& mask,
                      const SlotPaintCheckOptions& options, DetectedSlot* slot);

// What the paint shows next to a marking point at px whose separating line
// leaves along direction_rad: that line (cross-sections from refine_begin_m
// to refine_separating_end_m along it), and the entrance line leaving the
// point at a right angle to either side (refine_begin_m to refine_end_m),
// each fitted as RefineSlotCorners fits them, within max_angle_rad of the
// direction expected, and with paint in at least min_painted_share of its
// cross-sections in view (0: refine_min_sections of them suffice). A
// detector's weak points may be checked so: a junction of paint is there
// or it is not.
struct PointPaint {
  // Both lines had at least refine_min_sections cross-sections in view,
  // so that their absence means something.
  bool in_view = false;
  bool separating = false;
  bool entrance = false;
};
PointPaint MeasurePointPaint(const cv::Mat& grey, const cv::Mat& mask, const Eigen::Vector2d& px,
                             double direction_rad, double max_angle_rad, double min_painted_share,
                             const SlotPaintCheckOptions& options);

}  // namespace parkslam::perception

#endif  // PARKSLAM_PERCEPTION_SLOT_PAINT_CHECK_H_
