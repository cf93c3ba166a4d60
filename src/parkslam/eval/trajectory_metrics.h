#ifndef PARKSLAM_EVAL_TRAJECTORY_METRICS_H_
#define PARKSLAM_EVAL_TRAJECTORY_METRICS_H_

#include <map>

#include "parkslam/common/se2.h"
#include "parkslam/common/trajectory.h"

namespace parkslam::eval {

struct TrajectoryMetricsOptions {
  // Align the estimate onto the truth (rigid SE(2), no scale) before the
  // absolute errors. Relative errors never use the alignment.
  bool align = true;
  // Truth path length of the segments of the relative pose error.
  double rpe_segment_m = 10.0;
  // Truth path length of the segments of the drift figures.
  double drift_segment_m = 100.0;
};

struct TrajectoryMetrics {
  int matched_poses = 0;
  // Truth path length over the matched time span.
  double length_m = 0.0;
  // Absolute trajectory error: position error after the alignment.
  double ate_rmse_m = 0.0;
  double ate_mean_m = 0.0;
  double ate_max_m = 0.0;
  // Absolute yaw error after the alignment.
  double yaw_rmse_rad = 0.0;
  double yaw_max_rad = 0.0;
  // Relative pose error over rpe_segment_m of truth path; NaN when the
  // matched path is shorter than one segment.
  double rpe_trans_rmse_m = 0.0;
  double rpe_yaw_rmse_rad = 0.0;
  // Mean translational relative error over drift_segment_m segments (named
  // for the default 100 m segment); NaN when the path is shorter.
  double drift_per_100m_m = 0.0;
  // 100 * drift_per_100m_m / drift_segment_m.
  double drift_percent = 0.0;
  // The alignment used: aligned estimate = T_truth_estimate * estimate
  // (identity when !align).
  SE2 T_truth_estimate;
};

// Compares an estimated trajectory with the truth. Each estimate pose is
// paired with the truth interpolated at its timestamp; estimate poses outside
// the truth's time span are dropped. The truth must be sorted by time; the
// estimate need not be. Relative errors start at every matched pose and end at
// the first later pose at least one segment of truth path further on (O(n)).
// Throws std::invalid_argument when fewer than 2 timestamps overlap, when the
// truth is unsorted, or for non-positive segment lengths.
TrajectoryMetrics EvaluateTrajectory(const Trajectory& truth, const Trajectory& estimate,
                                     const TrajectoryMetricsOptions& options = {});

// RMS position error of poses matched by vertex id (a pose graph against its
// truth), after the rigid alignment that minimises it (AlignPointSets), so
// that the gauge of the solution does not count. Ids of the estimate missing
// from the truth are skipped. Throws std::invalid_argument when fewer than 2
// ids match.
double AlignedPositionRmse(const std::map<int, SE2>& estimate, const std::map<int, SE2>& truth);

}  // namespace parkslam::eval

#endif  // PARKSLAM_EVAL_TRAJECTORY_METRICS_H_
