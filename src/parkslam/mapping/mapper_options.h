#ifndef PARKSLAM_MAPPING_MAPPER_OPTIONS_H_
#define PARKSLAM_MAPPING_MAPPER_OPTIONS_H_

#include <string>

#include "parkslam/common/lot_constants.h"

namespace parkslam::mapping {

enum class RobustMode { kMaxMixture, kNone };
enum class MappingMode { kOnline, kBatch };
enum class TrustRegion { kLevenbergMarquardt, kDogleg };

struct MapperOptions {
  RobustMode robust = RobustMode::kMaxMixture;
  MappingMode mode = MappingMode::kBatch;

  // Keyframes: a slot or tag frame with observations becomes one after this
  // much motion since the last keyframe; a frame without any only after the
  // longer idle thresholds (keeping the odometry chain short where nothing
  // is seen).
  double keyframe_distance_m = 0.1;
  double keyframe_yaw_rad = 0.05;
  double idle_keyframe_distance_m = 2.0;
  double keyframe_interval_s = 2.0;

  // Observation model. Slot corners: the detector's sigma, at least
  // min_corner_sigma_m; guessed far corners only loosely.
  double min_corner_sigma_m = 0.03;
  double guessed_corner_sigma_m = 0.5;

  // The rectangular constraint (paper III-A): angles with high confidence,
  // side lengths with lower confidence. Observed slot angles within
  // right_angle_tolerance_rad of 90 degrees are taken as right angles.
  double shape_angle_sigma_rad = 0.0175;
  double shape_length_sigma_m = 0.1;
  double right_angle_tolerance_rad = 0.17;

  // Association (paper III-C): candidates by ID within id_search_radius_m,
  // nearest neighbours whose entrance corners lie within nn_search_radius_m
  // of the prediction.
  double id_hypothesis_min = 0.05;
  double id_confidence_min = 0.5;  // a "confident" reading (robust none)
  double id_search_radius_m = 6.0;
  double nn_search_radius_m = 2.0;
  int max_candidates = 6;
  // Prediction uncertainty added to the corners when choosing at
  // association time: base plus growth per metre since the last solve.
  double prediction_sigma_m = 0.05;
  double prediction_sigma_per_m = 0.01;

  // Max-Mixture: candidate weight floor (a neighbour the ID does not
  // support) and the null (new slot / outlier) component. A single
  // candidate of weight w wins over the null iff
  // chi2 < null_chi2 + 2 log(w / null_weight).
  double geometry_weight = 0.05;
  double null_weight = 0.05;
  double null_chi2 = 40.0;

  // Slot management.
  double merge_distance_m = 0.6;  // both entrance corners this close: one slot
  int min_observations = 3;       // fewer: dropped from the map as spurious
  double id_min_votes = 1.5;      // summed reading probability to name a slot
  // Two slots cannot share floor: at the end, a slot without an ID that
  // overlaps a named or better-observed slot by more than this share of
  // the smaller one's area is dropped (a wrong pairing across real slots,
  // which the merge by entrance corners cannot catch). Neighbours in a
  // consistent map overlap by their corners' error only (under 1 % of
  // their area).
  double max_overlap_share = 0.25;

  // Solver.
  int window_keyframes = 30;  // online: free keyframes per update
  // A landmark seen in the window brings at most this many of its older
  // observations (the latest; their poses held fixed) into the windowed
  // solve: enough to hold it where its history put it, and a bounded
  // update however often the car comes back (docs/robustness.md, "Soak").
  // The final solve takes every observation. 0: all of them.
  int window_history_observations = 40;
  // Memory that does not grow with the drive: once the stored records
  // (slot and tag observations) reach twice their count after the last
  // check, and at least retire_check_min_records, each landmark keeps its
  // latest max_records_per_landmark records outside the window; the older
  // ones are retired: their ID votes and counts stay with the slot they
  // chose, and they no longer enter any solve, the final one included. A
  // drive that passes each slot a few times never reaches the cap, so its
  // map is the same (docs/robustness.md, "Soak"). 0: keep every record.
  int max_records_per_landmark = 200;
  int retire_check_min_records = 16384;
  // On such a long drive (once retire_check_min_records were stored), slots
  // that the car made twice are merged every this many keyframes instead
  // of only at the end, so that revisits do not pile up candidates and
  // windowed work. 0: only at the end.
  int online_merge_every_keyframes = 600;
  // At the same times, a slot seen fewer than min_observations times, and
  // last seen more than this many keyframes ago, is dropped with its
  // records: a false detection, which would otherwise stay a landmark for
  // good and, one every few seconds, slow every update (docs/robustness.md,
  // "Soak").
  int prune_unconfirmed_after_keyframes = 300;
  int online_iterations = 5;
  // Online: the full graph (every keyframe, slot and tag) is solved in a
  // background thread (background_solve.h) every this many seconds of
  // drive, at most background_iterations, and its solution laid into the
  // map; 0: windowed updates only (docs/mapping.md, "Online at batch
  // accuracy"). With background_wait, a solve started at time t is laid in
  // at the first keyframe from t + background_solve_every_s on, waiting for
  // it there if need be: the same map on every machine, and what a car
  // whose solve fits that time sees. Without it, at the first keyframe
  // after it finished: a live car that must never wait.
  double background_solve_every_s = 2.0;
  int background_iterations = 20;
  bool background_wait = true;
  int batch_window_every = 10;  // batch: a windowed solve every n keyframes
  int final_iterations = 50;
  int final_rounds = 2;  // final solve, merge, re-choose, repeat
  TrustRegion trust_region = TrustRegion::kLevenbergMarquardt;
  // Measured (docs/results/solver_comparison.md): the same maps as the
  // default 1e4 in about half the time.
  double initial_trust_region_radius = 1e8;
  // The wheel speed's scale error as one unknown of the whole graph
  // (OdometryFactor), with the odometry's wheel_scale_sigma as its prior;
  // false: the dead reckoning's distances taken as they come. Off by
  // default: on pixels the top view's own scale error (about 0.1 % on the
  // default lot) enters the estimate and the map grows by it
  // (docs/mapping.md, "The wheel's scale").
  bool estimate_wheel_scale = false;

  // The corner sigmas the map states (docs/mapping.md, "How sure a
  // corner is"). A corner seen: with corner_sigma_from_graph, its marginal
  // covariance in the final graph relative to the map's other seen corners
  // (map_graph.h, ComputeCornerCovariances; the sigma is the root of half
  // its trace), which holds the drive's drift between loop closures; else,
  // seen n times, corner_evidence_sigma_m / sqrt(n). Either way combined
  // with corner_sigma_floor_m, what the graph does not model: the front
  // end's errors repeat between sightings of one pass, they are not
  // independent. Far corners never seen come from the row (back_line.h):
  // from a neighbour's depth with row_depth_sigma_m, or the standard
  // depth's guess with depth_prior_sigma_m, the spread of real slots'
  // depths.
  bool corner_sigma_from_graph = true;
  double corner_evidence_sigma_m = 0.05;
  double corner_sigma_floor_m = 0.010;
  double row_depth_sigma_m = 0.05;
  double depth_prior_sigma_m = 0.4;

  double tag_size_m = kDefaultTagSize_m;

  bool IsValid(std::string* error) const;

  // The field list, walked by the options file reader (io/options_yaml.h).
  // Not listed: robust, mode, trust_region (choices set on the command line).
  template <typename V>
  void VisitFields(V& v) {
    v("keyframe_distance_m", keyframe_distance_m);
    v("keyframe_yaw_rad", keyframe_yaw_rad);
    v("idle_keyframe_distance_m", idle_keyframe_distance_m);
    v("keyframe_interval_s", keyframe_interval_s);
    v("min_corner_sigma_m", min_corner_sigma_m);
    v("guessed_corner_sigma_m", guessed_corner_sigma_m);
    v("shape_angle_sigma_rad", shape_angle_sigma_rad);
    v("shape_length_sigma_m", shape_length_sigma_m);
    v("right_angle_tolerance_rad", right_angle_tolerance_rad);
    v("id_hypothesis_min", id_hypothesis_min);
    v("id_confidence_min", id_confidence_min);
    v("id_search_radius_m", id_search_radius_m);
    v("nn_search_radius_m", nn_search_radius_m);
    v("max_candidates", max_candidates);
    v("prediction_sigma_m", prediction_sigma_m);
    v("prediction_sigma_per_m", prediction_sigma_per_m);
    v("geometry_weight", geometry_weight);
    v("null_weight", null_weight);
    v("null_chi2", null_chi2);
    v("merge_distance_m", merge_distance_m);
    v("min_observations", min_observations);
    v("id_min_votes", id_min_votes);
    v("max_overlap_share", max_overlap_share);
    v("window_keyframes", window_keyframes);
    v("window_history_observations", window_history_observations);
    v("max_records_per_landmark", max_records_per_landmark);
    v("retire_check_min_records", retire_check_min_records);
    v("online_merge_every_keyframes", online_merge_every_keyframes);
    v("prune_unconfirmed_after_keyframes", prune_unconfirmed_after_keyframes);
    v("online_iterations", online_iterations);
    v("background_solve_every_s", background_solve_every_s);
    v("background_iterations", background_iterations);
    v("background_wait", background_wait);
    v("batch_window_every", batch_window_every);
    v("final_iterations", final_iterations);
    v("final_rounds", final_rounds);
    v("initial_trust_region_radius", initial_trust_region_radius);
    v("estimate_wheel_scale", estimate_wheel_scale);
    v("corner_sigma_from_graph", corner_sigma_from_graph);
    v("corner_evidence_sigma_m", corner_evidence_sigma_m);
    v("corner_sigma_floor_m", corner_sigma_floor_m);
    v("row_depth_sigma_m", row_depth_sigma_m);
    v("depth_prior_sigma_m", depth_prior_sigma_m);
    v("tag_size_m", tag_size_m);
  }
};

}  // namespace parkslam::mapping

#endif  // PARKSLAM_MAPPING_MAPPER_OPTIONS_H_
