#include "parkslam/options/option_ranges.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <type_traits>

#include "parkslam/common/angles.h"
#include "parkslam/common/field_checker.h"
#include "parkslam/common/plausible_ranges.h"

namespace parkslam {
namespace {

constexpr double kHalfPi = kPi / 2;

// [min, max], (0, max], (min, max) and [min, max) rows.
constexpr OptionRange In(std::string_view key, double min, double max, std::string_view unit,
                         std::string_view why) {
  return {key, min, max, false, false, unit, why};
}
constexpr OptionRange Pos(std::string_view key, double max, std::string_view unit,
                          std::string_view why) {
  return {key, 0.0, max, true, false, unit, why};
}
constexpr OptionRange Open(std::string_view key, double min, double max, std::string_view unit,
                           std::string_view why) {
  return {key, min, max, true, true, unit, why};
}
constexpr OptionRange InOpenMax(std::string_view key, double min, double max, std::string_view unit,
                                std::string_view why) {
  return {key, min, max, false, true, unit, why};
}

// The reasons shared by many rows.
constexpr std::string_view kShare = "a probability, confidence or share";
constexpr std::string_view kScale = "pixels per metre of a top view or a patch; 60 by default";
constexpr std::string_view kSlotSize =
    "a slot's side or a part of it: 2.5 m wide, 5.3 m deep, 6 m parallel (kMaxSlotSide_m 10)";
constexpr std::string_view kLine = "a painted line: 0.1 to 0.2 m wide";
constexpr std::string_view kTolerance = "a tolerance in the top view, which spans 10 m";
constexpr std::string_view kAngle = "an angle from straight up to square";
constexpr std::string_view kSigma =
    "a position sigma: beyond 10 m it says nothing among 2.5 m slots (kMaxPositionSigma_m)";
constexpr std::string_view kRelativeSigma = "a sigma per metre of range: 1 m/m is all of it";
constexpr std::string_view kAngleSigma = "an angle sigma: beyond half a turn it says nothing";
constexpr std::string_view kGrey = "a grey level in [0, 255]";
constexpr std::string_view kNear =
    "a distance around the car: its top view spans 10 m, its tags are used to 20 m";
constexpr std::string_view kSearch = "a search radius around the car or a prediction";
constexpr std::string_view kCount = "a count of points, lines or sections in one view";
constexpr std::string_view kKeyframes = "a count of keyframes: a 600 m drive makes about 6,000";
constexpr std::string_view kIterations = "solver iterations; each one costs a solve";
constexpr std::string_view kTime = "a time on a drive; an hour is longer than any drive parks";
constexpr std::string_view kAccel = "an acceleration: 1 g is 9.8 m/s^2";

constexpr OptionRange kRanges[] = {
    // front_end.top_view
    In("front_end.top_view.size_px", 16, 4096, "px", "the top view's side; 600 by default"),
    In("front_end.top_view.extent_m", kMinTopViewSide_m, kMaxTopViewSide_m, "m",
       "the ground the top view spans (kMinTopViewSide_m, kMaxTopViewSide_m); 10 m by default"),
    In("front_end.top_view.center_x_m", -kMaxCameraOffset_m, kMaxCameraOffset_m, "m",
       "the view's centre ahead of the rear axle: on the vehicle (kMaxCameraOffset_m)"),
    In("front_end.top_view.blend_angle_rad", 0, kPi, "rad", "the angle two cameras blend over"),
    In("front_end.top_view.camera_priority_rad", -1.5, 1.5, "rad",
       "a camera's seam shift: less than a quarter turn"),
    Pos("front_end.top_view.seam_front_angle_rad", 1.57, "rad", kAngle),
    Pos("front_end.top_view.seam_rear_angle_rad", 1.57, "rad", kAngle),
    Pos("front_end.top_view.footprint_length_m", kMaxVehicleLength_m, "m",
        "the car's body (kMaxVehicleLength_m)"),
    Pos("front_end.top_view.footprint_width_m", kMaxVehicleWidth_m, "m",
        "the car's body (kMaxVehicleWidth_m)"),
    In("front_end.top_view.footprint_rear_overhang_m", 0, kMaxVehicleLength_m, "m",
       "the car's body (kMaxVehicleLength_m)"),
    // front_end.slots
    // (front_end.learned_slots.classical_options.* takes these rows)
    Open("front_end.slots.pixels_per_m", 1, 1000, "px/m", kScale),
    Open("front_end.slots.min_line_width_m", 0, 1, "m", kLine),
    Open("front_end.slots.max_line_width_m", 0, 1, "m", kLine),
    Pos("front_end.slots.min_entrance_m", 2 * kMaxSlotSide_m, "m", kSlotSize),
    Pos("front_end.slots.max_entrance_m", 2 * kMaxSlotSide_m, "m", kSlotSize),
    Pos("front_end.slots.parallel_min_entrance_m", 2 * kMaxSlotSide_m, "m", kSlotSize),
    Pos("front_end.slots.standard_depth_m", 2 * kMaxSlotSide_m, "m", kSlotSize),
    Pos("front_end.slots.parallel_depth_m", 2 * kMaxSlotSide_m, "m", kSlotSize),
    Open("front_end.slots.max_direction_difference_rad", 0, kHalfPi, "rad", kAngle),
    Pos("front_end.slots.on_line_tolerance_m", 5, "m", kTolerance),
    In("front_end.slots.min_contrast_grey", 1, 255, "", kGrey),
    In("front_end.slots.local_contrast_factor", 1, 100, "", "a ratio of contrasts"),
    Pos("front_end.slots.local_window_m", 10, "m", kTolerance),
    Pos("front_end.slots.relative_contrast", 1, "", kShare),
    Pos("front_end.slots.line_relative_contrast", 1, "", kShare),
    In("front_end.slots.min_two_sided_share", 0, 1, "", kShare),
    Pos("front_end.slots.min_arm_m", 2 * kMaxSlotSide_m, "m", kSlotSize),
    Pos("front_end.slots.min_stem_m", 2 * kMaxSlotSide_m, "m", kSlotSize),
    Pos("front_end.slots.max_clutter", 1, "", kShare),
    In("front_end.slots.max_lines_nearby", 0, 1000, "", kCount),
    Pos("front_end.slots.nearby_radius_m", 10, "m", kTolerance),
    Pos("front_end.slots.long_line_m", 2 * kMaxSlotSide_m, "m", kSlotSize),
    Pos("front_end.slots.max_width_deviation", 10, "",
        "a line width's deviation relative to its width"),
    InOpenMax("front_end.slots.mask_margin_m", 0, 1, "m", kTolerance),
    In("front_end.slots.max_merge_gap_m", 0, 5, "m", kTolerance),
    In("front_end.slots.end_tolerance_px", 0, 1000, "px", kTolerance),
    Open("front_end.slots.min_junction_angle_rad", 0, kHalfPi, "rad", kAngle),
    In("front_end.slots.max_vehicle_depth_in_row_m", 0, 2 * kMaxSlotSide_m, "m", kSlotSize),
    // front_end.ids
    Pos("front_end.ids.pixels_per_m", 1000, "px/m", kScale),
    In("front_end.ids.id_setback_m", 0, 5, "m", "a painted ID's distance from the entrance"),
    Pos("front_end.ids.id_height_m", 3, "m", "a painted ID's height: 0.6 m by default"),
    In("front_end.ids.max_digits", 1, 6, "", "an ID's digits"),
    Pos("front_end.ids.min_hypothesis_probability", 1, "", kShare),
    In("front_end.ids.min_digit_probability", 0, 1, "", kShare),
    In("front_end.ids.max_offset_m", 0, 1, "m", "a painted ID's shift from its place"),
    In("front_end.ids.min_paint_ratio", 0, 1, "", kShare),
    // front_end.learned_slots
    In("front_end.learned_slots.input_size_px", 16, 4096, "px",
       "the network's input side (a multiple of 16)"),
    Open("front_end.learned_slots.min_confidence", 0, 1, "", kShare),
    In("front_end.learned_slots.min_partner_confidence", 0, 1, "", kShare),
    In("front_end.learned_slots.weak_point_min_confidence", 0, 1, "", kShare),
    Pos("front_end.learned_slots.weak_point_max_angle_rad", kHalfPi, "rad", kAngle),
    In("front_end.learned_slots.weak_point_min_painted_share", 0, 1, "", kShare),
    In("front_end.learned_slots.flips", 1, 4, "", "1, 2 or 4 flipped passes"),
    In("front_end.learned_slots.max_point_depth_towards_car_m", 0, 2 * kMaxSlotSide_m, "m",
       kSlotSize),
    In("front_end.learned_slots.nms_radius_px", 0, 1000, "px", kTolerance),
    In("front_end.learned_slots.border_margin_m", 0, 2, "m", kTolerance),
    In("front_end.learned_slots.pairing.pixels_per_m", 1, 1000, "px/m", kScale),
    Pos("front_end.learned_slots.pairing.min_entrance_m", 2 * kMaxSlotSide_m, "m", kSlotSize),
    Pos("front_end.learned_slots.pairing.max_entrance_m", 2 * kMaxSlotSide_m, "m", kSlotSize),
    Pos("front_end.learned_slots.pairing.parallel_min_entrance_m", 2 * kMaxSlotSide_m, "m",
        kSlotSize),
    Pos("front_end.learned_slots.pairing.standard_depth_m", 2 * kMaxSlotSide_m, "m", kSlotSize),
    Pos("front_end.learned_slots.pairing.parallel_depth_m", 2 * kMaxSlotSide_m, "m", kSlotSize),
    In("front_end.learned_slots.pairing.parallel_min_depth_in_view_m", 0, 10, "m", kSlotSize),
    In("front_end.learned_slots.pairing.border_width_check_m", 0, 10, "m", kSlotSize),
    Pos("front_end.learned_slots.pairing.border_width_share", 1, "", kShare),
    Open("front_end.learned_slots.pairing.max_direction_difference_rad", 0, kPi, "rad",
         "an angle between two directions"),
    In("front_end.learned_slots.pairing.on_line_tolerance_m", 0, 5, "m", kTolerance),
    InOpenMax("front_end.learned_slots.pairing.min_junction_angle_rad", 0, kHalfPi, "rad", kAngle),
    In("front_end.learned_slots.pairing.max_vehicle_depth_in_row_m", 0, 2 * kMaxSlotSide_m, "m",
       kSlotSize),
    Pos("front_end.learned_slots.extend_tolerance_m", 5, "m", kTolerance),
    Pos("front_end.learned_slots.paint_check.pixels_per_m", 1000, "px/m", kScale),
    In("front_end.learned_slots.paint_check.first_depth_m", 0, 2 * kMaxSlotSide_m, "m", kSlotSize),
    Pos("front_end.learned_slots.paint_check.depth_step_m", 2 * kMaxSlotSide_m, "m", kSlotSize),
    In("front_end.learned_slots.paint_check.depth_count", 2, 20, "", kCount),
    In("front_end.learned_slots.paint_check.min_depths_in_view", 2, 20, "", kCount),
    Pos("front_end.learned_slots.paint_check.min_share_in_view", 1, "", kShare),
    In("front_end.learned_slots.paint_check.end_margin_m", 0, 5, "m", kTolerance),
    Pos("front_end.learned_slots.paint_check.min_line_width_m", 1, "m", kLine),
    Pos("front_end.learned_slots.paint_check.max_line_width_m", 2, "m", kLine),
    In("front_end.learned_slots.paint_check.min_contrast_grey", 0, 255, "", kGrey),
    In("front_end.learned_slots.paint_check.own_line_share", 0, 1, "", kShare),
    Pos("front_end.learned_slots.paint_check.max_drift_m", 5, "m", kTolerance),
    In("front_end.learned_slots.paint_check.refine_begin_m", 0, 5, "m", kSlotSize),
    Pos("front_end.learned_slots.paint_check.refine_end_m", 5, "m", kSlotSize),
    Pos("front_end.learned_slots.paint_check.refine_separating_end_m", 5, "m", kSlotSize),
    Pos("front_end.learned_slots.paint_check.refine_half_window_m", 2, "m", kTolerance),
    In("front_end.learned_slots.paint_check.refine_min_sections", 2, 1000, "", kCount),
    Pos("front_end.learned_slots.classical_match_px", 1000, "px", kTolerance),
    Pos("front_end.learned_slots.classical_match_rad", kPi, "rad", "an angle between directions"),
    // front_end.learned_ids
    Pos("front_end.learned_ids.pixels_per_m", 1000, "px/m", kScale),
    In("front_end.learned_ids.id_setback_m", 0, 5, "m",
       "a painted ID's distance from the entrance"),
    Pos("front_end.learned_ids.id_height_m", 3, "m", "a painted ID's height: 0.6 m by default"),
    In("front_end.learned_ids.min_hypothesis_probability", 0, 1, "", kShare),
    In("front_end.learned_ids.min_digit_probability", 0, 1, "", kShare),
    In("front_end.learned_ids.min_end_probability", 0, 1, "", kShare),
    In("front_end.classical_id_min_confidence", 0, 1, "", kShare),
    // front_end.tags
    Pos("front_end.tags.tag_size_m", kMaxTagSize_m, "m",
        "a tag on a wall or pillar (kMaxTagSize_m); ours are 0.488 m"),
    In("front_end.tags.quad_decimate", 1, 16, "",
       "libapriltag's decimation: beyond 16 a 640 px image has 40 px left"),
    In("front_end.tags.max_hamming", 0, 3, "", "bits corrected in tag36h11"),
    Pos("front_end.tags.max_range_m", kMaxObservationRange_m, "m",
        "what the car reports (kMaxObservationRange_m)"),
    Pos("front_end.tags.max_angle_disagreement_rad", kPi, "rad", "an angle between directions"),
    In("front_end.tag_min_height_m", 0, 10, "m", "a tag's height under a ceiling"),
    In("front_end.tag_max_height_m", 0, 10, "m", "a tag's height under a ceiling"),
    In("front_end.tag_min_range_m", 0, kMaxObservationRange_m, "m",
       "what the car reports (kMaxObservationRange_m)"),
    In("front_end.tag_windows.sigmas", 0, 10, "", "a window's half size in sigmas"),
    In("front_end.tag_windows.margin_px", 0, 1000, "px", "around a window, in a 640 px image"),
    In("front_end.tag_windows.min_decimated_px", 1, 1000, "px", "a window's size after decimation"),
    In("front_end.tag_windows.max_band_share", 0, 1, "", kShare),
    Pos("front_end.corner_sigma_m", kMaxPositionSigma_m, "m", kSigma),
    Pos("front_end.corner_sigma_per_m", kMaxRelativeSigma, "m/m", kRelativeSigma),
    Pos("front_end.tag_range_sigma_m", kMaxPositionSigma_m, "m", kSigma),
    Pos("front_end.tag_range_sigma_per_m", kMaxRelativeSigma, "m/m", kRelativeSigma),
    Pos("front_end.tag_bearing_sigma_rad", kMaxAngleSigma_rad, "rad", kAngleSigma),
    Pos("front_end.tag_yaw_sigma_rad", kMaxAngleSigma_rad, "rad", kAngleSigma),
    Pos("front_end.tag_yaw_sigma_per_m", kMaxRelativeSigma, "rad/m",
        "an angle sigma per metre of range"),
    // mapper
    Pos("mapper.keyframe_distance_m", kMaxObservationRange_m, "m", kNear),
    Pos("mapper.keyframe_yaw_rad", kPi, "rad", "a turn between keyframes: half a turn at most"),
    Pos("mapper.idle_keyframe_distance_m", kMaxObservationRange_m, "m", kNear),
    Pos("mapper.keyframe_interval_s", 3600, "s", kTime),
    Pos("mapper.min_corner_sigma_m", kMaxPositionSigma_m, "m", kSigma),
    Pos("mapper.guessed_corner_sigma_m", kMaxPositionSigma_m, "m", kSigma),
    Pos("mapper.shape_angle_sigma_rad", kMaxAngleSigma_rad, "rad", kAngleSigma),
    Pos("mapper.shape_length_sigma_m", kMaxPositionSigma_m, "m", kSigma),
    Open("mapper.right_angle_tolerance_rad", 0, kHalfPi, "rad", kAngle),
    In("mapper.id_hypothesis_min", 0, 1, "", kShare),
    In("mapper.id_confidence_min", 0, 1, "", kShare),
    Pos("mapper.id_search_radius_m", kMaxObservationRange_m, "m", kSearch),
    Pos("mapper.nn_search_radius_m", kMaxObservationRange_m, "m", kSearch),
    In("mapper.max_candidates", 1, 1000, "", "associations weighed per observation"),
    In("mapper.prediction_sigma_m", 0, kMaxPositionSigma_m, "m", kSigma),
    In("mapper.prediction_sigma_per_m", 0, kMaxRelativeSigma, "m/m", kRelativeSigma),
    Pos("mapper.geometry_weight", 1, "", kShare),
    Pos("mapper.null_weight", 1, "", kShare),
    Pos("mapper.null_chi2", 10000, "",
        "a chi-square threshold: 40 by default, 10,000 is a 100-sigma outlier"),
    In("mapper.merge_distance_m", 0, kMaxPositionSigma_m, "m", kSearch),
    In("mapper.min_observations", 1, 100000, "", "observations of one landmark"),
    Pos("mapper.id_min_votes", 100000, "", "votes from observations of one landmark"),
    Pos("mapper.max_overlap_share", 1, "", kShare),
    In("mapper.window_keyframes", 2, 100000, "", kKeyframes),
    In("mapper.window_history_observations", 0, 1e6, "", "observations kept per landmark"),
    In("mapper.max_records_per_landmark", 0, 1e6, "", "observations kept per landmark"),
    In("mapper.retire_check_min_records", 1, 1e8, "", "observations in the whole graph"),
    In("mapper.online_merge_every_keyframes", 0, 1e6, "", kKeyframes),
    In("mapper.prune_unconfirmed_after_keyframes", 0, 1e6, "", kKeyframes),
    In("mapper.online_iterations", 1, 1000, "", kIterations),
    In("mapper.background_solve_every_s", 0, 3600, "s", kTime),
    In("mapper.background_iterations", 1, 1000, "", kIterations),
    In("mapper.batch_window_every", 1, 1e6, "", kKeyframes),
    In("mapper.final_iterations", 1, 1000, "", kIterations),
    In("mapper.final_rounds", 1, 100, "", "rounds of association and solve at the end"),
    In("mapper.initial_trust_region_radius", 1e-32, 1e16, "",
       "Ceres's own bounds: outside them it leaves the map unsolved without a word"),
    Pos("mapper.corner_evidence_sigma_m", kMaxPositionSigma_m, "m", kSigma),
    In("mapper.corner_sigma_floor_m", 0, kMaxPositionSigma_m, "m", kSigma),
    Pos("mapper.row_depth_sigma_m", kMaxPositionSigma_m, "m", kSigma),
    Pos("mapper.depth_prior_sigma_m", kMaxPositionSigma_m, "m", kSigma),
    Pos("mapper.tag_size_m", kMaxTagSize_m, "m",
        "a tag on a wall or pillar (kMaxTagSize_m); ours are 0.488 m"),
    // localizer
    Pos("localizer.corner_sigma_floor_m", kMaxPositionSigma_m, "m", kSigma),
    In("localizer.map_corner_sigma_floor_m", 0, kMaxPositionSigma_m, "m", kSigma),
    In("localizer.tag_map_sigma_m", 0, kMaxPositionSigma_m, "m", kSigma),
    In("localizer.tag_map_yaw_sigma_rad", 0, kMaxAngleSigma_rad, "rad", kAngleSigma),
    In("localizer.map_yaw_sigma_rad", 0, kMaxAngleSigma_rad, "rad", kAngleSigma),
    In("localizer.wheel_scale_walk_per_sqrt_m", 0, 0.1, "per sqrt(m)",
       "a scale's random walk: at 0.1 the distance is unknown by 100 % after 100 m"),
    In("localizer.id_min_confidence", 0, 1, "", kShare),
    Pos("localizer.nn_radius_m", kMaxObservationRange_m, "m", kSearch),
    Open("localizer.gate_probability", 0.5, 1, "",
         "a gate's probability: below 0.5 it gates out "
         "most right associations, at 1 none"),
    Pos("localizer.lost_after_s", 3600, "s", kTime),
    In("localizer.lost_min_rejected", 1, 100000, "", "observations rejected in a row"),
    Pos("localizer.lost_position_sigma_m", kMaxObservationRange_m, "m", kNear),
    Pos("localizer.reloc_window_s", 3600, "s", kTime),
    Pos("localizer.reloc_inlier_m", kMaxPositionSigma_m, "m", kSearch),
    In("localizer.reloc_min_inliers", 2, 1000, "", "landmarks matched in one window"),
    In("localizer.reloc_min_landmarks", 1, 1000, "", "landmarks matched in one window"),
    Pos("localizer.reloc_ambiguity_ratio", 1, "", kShare),
    Pos("localizer.reloc_position_sigma_m", kMaxPositionSigma_m, "m", kSigma),
    Pos("localizer.reloc_yaw_sigma_rad", kMaxAngleSigma_rad, "rad", kAngleSigma),
    Pos("localizer.entrance_position_sigma_m", kMaxPositionSigma_m, "m", kSigma),
    Pos("localizer.entrance_yaw_sigma_rad", kMaxAngleSigma_rad, "rad", kAngleSigma),
    // follower
    Pos("follower.lookahead_base_m", kMaxObservationRange_m, "m", kNear),
    In("follower.lookahead_per_mps", 0, 100, "s", "lookahead per m/s: seconds ahead"),
    Pos("follower.max_lateral_accel_mps2", kMaxAcceleration_mps2, "m/s^2", kAccel),
    Pos("follower.max_accel_mps2", kMaxAcceleration_mps2, "m/s^2", kAccel),
    Pos("follower.max_decel_mps2", kMaxAcceleration_mps2, "m/s^2", kAccel),
    Pos("follower.stop_distance_m", kMaxObservationRange_m, "m", kNear),
    Pos("follower.stop_speed_mps", kMaxWheelSpeed_mps, "m/s", "a car's speed (kMaxWheelSpeed_mps)"),
    Pos("follower.search_window_m", kMaxObservationRange_m, "m", kNear),
    In("follower.curvature_horizon_m", 0, kMaxObservationRange_m, "m", kNear),
    In("follower.curvature_lookbehind_m", 0, kMaxObservationRange_m, "m", kNear),
};

constexpr std::string_view kClassicalBlock = "front_end.learned_slots.classical_options.";
constexpr std::string_view kSlotsBlock = "front_end.slots.";

// Collects every number under its full key.
class NumberCollector {
 public:
  explicit NumberCollector(std::vector<std::pair<std::string, double>>* out,
                           std::string prefix = "")
      : out_(out), prefix_(std::move(prefix)) {}

  template <typename T>
  void operator()(const char* key, T& field) {
    const std::string full = prefix_ + key;
    if constexpr (std::is_same_v<T, double> || std::is_same_v<T, float> || std::is_same_v<T, int>) {
      out_->emplace_back(full, static_cast<double>(field));
    } else if constexpr (std::is_same_v<T, std::vector<double>>) {
      for (const double value : field) out_->emplace_back(full, value);
    } else if constexpr (std::is_same_v<T, Eigen::Vector2d>) {
      out_->emplace_back(full, field.x());
      out_->emplace_back(full, field.y());
    } else if constexpr (requires(NumberCollector & c) { field.VisitFields(c); }) {
      NumberCollector nested(out_, full + ".");
      field.VisitFields(nested);
    }
  }

 private:
  std::vector<std::pair<std::string, double>>* out_;
  std::string prefix_;
};

std::string Number(double value) {
  if (value == kPi) return "π";
  if (value == kHalfPi) return "π/2";
  return Limit(value);
}

}  // namespace

bool OptionRange::Contains(double value) const {
  if (!std::isfinite(value)) return false;
  const bool above = min_open ? value > min : value >= min;
  const bool below = max_open ? value < max : value <= max;
  return above && below;
}

std::string OptionRange::Text() const {
  std::string text(min_open ? "(" : "[");
  text.append(Number(min)).append(", ").append(Number(max)).append(max_open ? ")" : "]");
  if (!unit.empty()) text.append(" ").append(unit);
  return text;
}

std::span<const OptionRange> OptionRanges() { return kRanges; }

const OptionRange* FindOptionRange(std::string_view key) {
  std::string own(key);
  if (key.starts_with(kClassicalBlock)) {
    own = std::string(kSlotsBlock) + std::string(key.substr(kClassicalBlock.size()));
  }
  const auto it = std::find_if(std::begin(kRanges), std::end(kRanges),
                               [&](const OptionRange& row) { return row.key == own; });
  return it == std::end(kRanges) ? nullptr : &*it;
}

std::vector<std::pair<std::string, double>> NumericOptions(const AlgorithmOptions& options) {
  std::vector<std::pair<std::string, double>> numbers;
  AlgorithmOptions copy = options;  // VisitFields() is not const
  NumberCollector collector(&numbers);
  copy.VisitFields(collector);
  return numbers;
}

bool CheckOptionRanges(const AlgorithmOptions& options, std::string* error) {
  FieldChecker c(error);
  for (const auto& [key, value] : NumericOptions(options)) {
    const OptionRange* range = FindOptionRange(key);
    c.Require(range != nullptr, key, "has no plausible range in options/option_ranges.cc");
    if (range == nullptr) break;
    c.Require(range->Contains(value), key,
              Limit(value) + " is outside the plausible range " + range->Text());
  }
  return c.ok();
}

std::string OptionRangesMarkdown() {
  std::string out =
      "| option | plausible range | why |\n"
      "|---|---|---|\n";
  for (const OptionRange& row : kRanges) {
    std::string text = row.Text();
    out += "| `" + std::string(row.key) + "` | " + text + " | " + std::string(row.why) + " |\n";
  }
  return out;
}

}  // namespace parkslam
