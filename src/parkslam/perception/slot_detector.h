#ifndef PARKSLAM_PERCEPTION_SLOT_DETECTOR_H_
#define PARKSLAM_PERCEPTION_SLOT_DETECTOR_H_

// Parking-slot detection in the top view (paper III-A): marking points, the
// T- and L-shaped junctions where a separating line meets the entrance
// line, are found from the painted lines; pairs of them at a slot's width
// with consistent directions form entrance lines; an entrance-line
// candidate with more than two marking points on it is removed, and
// candidates of implausible length are discarded. The far corners are
// guessed from the standard slot depth.
//
// Top-view pixels are 0-based, (0, 0) the centre of the top-left pixel,
// x to the right and y down (camera/top_view.h).

#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "parkslam/common/lot_constants.h"

namespace parkslam::perception {

enum class MarkingShape { kT, kL };
const char* ToString(MarkingShape shape);

// A junction of painted lines. direction_rad is the image angle
// atan2(dy, dx) of the separating line leaving the junction into the slots
// (the ps2.0 labels' convention).
struct MarkingPoint {
  Eigen::Vector2d px = Eigen::Vector2d::Zero();
  double direction_rad = 0.0;
  MarkingShape shape = MarkingShape::kT;
  double score = 0.0;  // in [0, 1]
};

// One detected slot. corners_px follows the project's corner order
// (sensor_data.h): 0 and 1 end the entrance line, 2 lies behind 1 and 3
// behind 0. Corners 2 and 3 are guessed from the standard depth.
struct DetectedSlot {
  std::array<Eigen::Vector2d, 4> corners_px{};
  std::array<bool, 4> corner_observed{true, true, false, false};
  Eigen::Vector2d depth_dir_px = Eigen::Vector2d::UnitY();  // into the slot
  std::array<int, 2> marking_points{-1, -1};                // indices of corners 0 and 1
  double confidence = 0.0;
};

struct SlotDetectorOptions {
  double pixels_per_m = 60.0;  // 600 px for 10 m (ps2.0)
  // Painted lines: their width range.
  double min_line_width_m = 0.06;
  double max_line_width_m = 0.30;
  // Entrance lengths accepted as slots (perpendicular or angled slots, and
  // parallel ones); shorter or longer candidates are discarded.
  double min_entrance_m = 2.0;
  double max_entrance_m = 7.5;
  // Entrances longer than this belong to parallel slots.
  double parallel_min_entrance_m = 4.0;
  double standard_depth_m = kStandardSlotDepth_m;
  double parallel_depth_m = 2.5;
  // The two marking points of one slot point the same way within this.
  double max_direction_difference_rad = 0.35;
  // A marking point within this of an entrance line between two others
  // counts as lying on it (paper: such candidates are removed).
  double on_line_tolerance_m = 0.25;
  // Paint stands above the floor (the grey image less its median over
  // twice the widest line) by at least min_contrast_grey grey levels and
  // local_contrast_factor times the mean response within local_window_m
  // around it. Lines are refined against relative_contrast of the
  // brightest paint in view (its 99.5th percentile), or a faint line
  // against line_relative_contrast of its own median peak, whichever is
  // lower (never below min_contrast_grey).
  double min_contrast_grey = 20.0;
  double local_contrast_factor = 2.0;
  double local_window_m = 1.0;
  double relative_contrast = 0.35;
  double line_relative_contrast = 0.5;
  // Paint is brighter than the floor on both sides: at least this share
  // of a line's centreline stands above both sides, one line width out, by
  // half its contrast over the darker side (the bright side of a shadow's
  // edge or a lit patch does not; digits beside a line hide a side only
  // in places).
  double min_two_sided_share = 0.5;
  // Arms of a junction are at least this long; junctions closer than this
  // are one marking point.
  double min_arm_m = 0.4;
  // The separating line leaving a marking point is at least this long in
  // view (painted digits' strokes are shorter).
  double min_stem_m = 0.7;
  // At most this share of the paint in a ring round a junction may lie off
  // its arms (painted digits and texture make cluttered junctions).
  double max_clutter = 0.15;
  // At most this many other lines pass within nearby_radius_m of a
  // junction (a car's body, grass or a textured wall make many).
  int max_lines_nearby = 4;
  double nearby_radius_m = 1.0;
  // Lines at least long_line_m long are slot lines; shorter lines of a
  // junction may differ from their median width by at most this share
  // (painted digits' strokes are thinner, merged strokes wider).
  double long_line_m = 1.2;
  double max_width_deviation = 0.25;
  // Junctions this close to masked or unseen pixels are ignored (the
  // border blends the image with what is masked); a typical line's width,
  // so that a line painted next to the car's footprint is still seen.
  double mask_margin_m = 0.1;
  // Collinear pieces of one line merge across gaps up to this.
  double max_merge_gap_m = 0.1;
  // A line ends at a junction when its end lies within half the other
  // line's width plus this.
  double end_tolerance_px = 4.0;
  // Lines meeting at less than this make no junction (angled slots meet
  // their entrance at 45 degrees or more).
  double min_junction_angle_rad = 0.6;
  // Slots open towards the car: their interior lies beyond the entrance as
  // seen from the image centre. Removes the false slots that a painted back
  // line and its junctions would make.
  bool require_entrance_facing_vehicle = true;
  // ... unless the car stands in the slot's row: the image centre less than
  // this past the entrance of a slot narrower than parallel_min_entrance_m,
  // as when it parks (0: never). A back line's junctions lie a slot's depth
  // (5.3 m) behind the entrance, and the car stands in the aisle in front of
  // it, over 6 m from them. Off here: on the synthetic validation set it
  // adds as many false slots as true ones to this detector (the learned
  // pairing, SlotPairingOptions, has it on).
  double max_vehicle_depth_in_row_m = 0.0;

  bool IsValid(std::string* error) const;

  // The field list, walked by the options file reader (io/options_yaml.h).
  template <typename V>
  void VisitFields(V& v) {
    v("pixels_per_m", pixels_per_m);
    v("min_line_width_m", min_line_width_m);
    v("max_line_width_m", max_line_width_m);
    v("min_entrance_m", min_entrance_m);
    v("max_entrance_m", max_entrance_m);
    v("parallel_min_entrance_m", parallel_min_entrance_m);
    v("standard_depth_m", standard_depth_m);
    v("parallel_depth_m", parallel_depth_m);
    v("max_direction_difference_rad", max_direction_difference_rad);
    v("on_line_tolerance_m", on_line_tolerance_m);
    v("min_contrast_grey", min_contrast_grey);
    v("local_contrast_factor", local_contrast_factor);
    v("local_window_m", local_window_m);
    v("relative_contrast", relative_contrast);
    v("line_relative_contrast", line_relative_contrast);
    v("min_two_sided_share", min_two_sided_share);
    v("min_arm_m", min_arm_m);
    v("min_stem_m", min_stem_m);
    v("max_clutter", max_clutter);
    v("max_lines_nearby", max_lines_nearby);
    v("nearby_radius_m", nearby_radius_m);
    v("long_line_m", long_line_m);
    v("max_width_deviation", max_width_deviation);
    v("mask_margin_m", mask_margin_m);
    v("max_merge_gap_m", max_merge_gap_m);
    v("end_tolerance_px", end_tolerance_px);
    v("min_junction_angle_rad", min_junction_angle_rad);
    v("require_entrance_facing_vehicle", require_entrance_facing_vehicle);
    v("max_vehicle_depth_in_row_m", max_vehicle_depth_in_row_m);
  }
};

// Whether a slot whose entrance runs through `a_px` and `b_px` and whose
// interior lies along the unit `depth_dir` opens as the options allow:
// away from the car at `centre_px`, or, unless it is `parallel`, towards it
// with the car less than max_vehicle_depth_m (at `pixels_per_m`) past the
// entrance, inside the slot's row.
bool SlotOpensAsAllowed(const Eigen::Vector2d& a_px, const Eigen::Vector2d& b_px,
                        const Eigen::Vector2d& depth_dir, const Eigen::Vector2d& centre_px,
                        double pixels_per_m, bool parallel, bool require_facing,
                        double max_vehicle_depth_m);

// A painted line's centreline found in the image, from end to end.
struct PaintedLine {
  Eigen::Vector2d a_px = Eigen::Vector2d::Zero(), b_px = Eigen::Vector2d::Zero();
  double width_px = 0.0;
};

struct SlotDetection {
  std::vector<PaintedLine> lines;
  std::vector<MarkingPoint> marking_points;
  std::vector<DetectedSlot> slots;
};

class SlotDetector {
 public:
  // Throws std::invalid_argument on invalid options.
  explicit SlotDetector(const SlotDetectorOptions& options = {});

  // Detects marking points and slots in an 8-bit grey (or BGR) top view.
  // Pixels where mask is zero (the car's footprint) are ignored; mask may
  // be empty. Regions of pure black (what no camera of a fused view sees)
  // are ignored as well.
  SlotDetection Detect(const cv::Mat& top_view, const cv::Mat& mask = cv::Mat()) const;

  const SlotDetectorOptions& options() const { return options_; }

 private:
  SlotDetectorOptions options_;
};

}  // namespace parkslam::perception

#endif  // PARKSLAM_PERCEPTION_SLOT_DETECTOR_H_
