#include "parkslam/eval/trajectory_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <vector>

#include "parkslam/common/alignment.h"
#include "parkslam/common/angles.h"

namespace parkslam::eval {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// One estimate pose and the truth at the same time.
struct PosePair {
  TimeNs t_ns = 0;
  SE2 T_map_truth;
  SE2 T_map_estimate;
  // Truth path length from the start of the truth to t_ns.
  double truth_arc_m = 0.0;
};

void ValidateInputs(const Trajectory& truth, const TrajectoryMetricsOptions& options) {
  if (!(options.rpe_segment_m > 0.0) || !(options.drift_segment_m > 0.0)) {
    throw std::invalid_argument(
        "EvaluateTrajectory: rpe_segment_m and drift_segment_m must be > 0");
  }
  const bool sorted =
      std::is_sorted(truth.begin(), truth.end(),
                     [](const TimedPose& a, const TimedPose& b) { return a.t_ns < b.t_ns; });
  if (!sorted) {
    throw std::invalid_argument("EvaluateTrajectory: truth is not sorted by time");
  }
}

// cumulative_m[k] = truth path length from truth[0] to truth[k].
std::vector<double> CumulativeLength(const Trajectory& truth) {
  std::vector<double> cumulative_m(truth.size(), 0.0);
  for (size_t k = 1; k < truth.size(); ++k) {
    cumulative_m[k] =
        cumulative_m[k - 1] +
        (truth[k].T_map_vehicle.translation() - truth[k - 1].T_map_vehicle.translation()).norm();
  }
  return cumulative_m;
}

// Truth path length up to t_ns, where the truth is at T_map_truth.
double ArcLengthAt(const Trajectory& truth, const std::vector<double>& cumulative_m, TimeNs t_ns,
                   const SE2& T_map_truth) {
  const auto after =
      std::lower_bound(truth.begin(), truth.end(), t_ns,
                       [](const TimedPose& pose, TimeNs t) { return pose.t_ns < t; });
  if (after == truth.begin()) return 0.0;
  const size_t before = static_cast<size_t>(after - truth.begin()) - 1;
  return cumulative_m[before] +
         (T_map_truth.translation() - truth[before].T_map_vehicle.translation()).norm();
}

std::vector<PosePair> MatchPoses(const Trajectory& truth, const Trajectory& estimate) {
  const std::vector<double> cumulative_m = CumulativeLength(truth);
  std::vector<PosePair> pairs;
  pairs.reserve(estimate.size());
  for (const TimedPose& pose : estimate) {
    const std::optional<SE2> T_map_truth = PoseAt(truth, pose.t_ns);
    if (!T_map_truth) continue;
    pairs.push_back({pose.t_ns, *T_map_truth, pose.T_map_vehicle,
                     ArcLengthAt(truth, cumulative_m, pose.t_ns, *T_map_truth)});
  }
  std::stable_sort(pairs.begin(), pairs.end(),
                   [](const PosePair& a, const PosePair& b) { return a.t_ns < b.t_ns; });
  if (pairs.size() < 2) {
    throw std::invalid_argument(
        "EvaluateTrajectory: estimate and truth overlap in fewer than 2 "
        "timestamps");
  }
  return pairs;
}

SE2 Alignment(const std::vector<PosePair>& pairs) {
  std::vector<Eigen::Vector2d> estimate_positions, truth_positions;
  estimate_positions.reserve(pairs.size());
  truth_positions.reserve(pairs.size());
  for (const PosePair& pair : pairs) {
    estimate_positions.push_back(pair.T_map_estimate.translation());
    truth_positions.push_back(pair.T_map_truth.translation());
  }
  return AlignPointSets(estimate_positions, truth_positions);
}

void FillAbsoluteErrors(const std::vector<PosePair>& pairs, const SE2& T_truth_estimate,
                        TrajectoryMetrics* metrics) {
  double sum_sq_m2 = 0.0, sum_m = 0.0, max_m = 0.0;
  double sum_sq_yaw = 0.0, max_yaw_rad = 0.0;
  for (const PosePair& pair : pairs) {
    const SE2 T_aligned = T_truth_estimate * pair.T_map_estimate;
    const double error_m = (T_aligned.translation() - pair.T_map_truth.translation()).norm();
    const double yaw_error_rad = std::abs(AngleDiff(T_aligned.yaw(), pair.T_map_truth.yaw()));
    sum_sq_m2 += error_m * error_m;
    sum_m += error_m;
    max_m = std::max(max_m, error_m);
    sum_sq_yaw += yaw_error_rad * yaw_error_rad;
    max_yaw_rad = std::max(max_yaw_rad, yaw_error_rad);
  }
  const double n = static_cast<double>(pairs.size());
  metrics->ate_rmse_m = std::sqrt(sum_sq_m2 / n);
  metrics->ate_mean_m = sum_m / n;
  metrics->ate_max_m = max_m;
  metrics->yaw_rmse_rad = std::sqrt(sum_sq_yaw / n);
  metrics->yaw_max_rad = max_yaw_rad;
}

struct RelativeErrors {
  std::vector<double> translation_m;
  std::vector<double> yaw_rad;
};

// For every start i, the first later pair j with truth path >= segment_m from
// i. The arc length never falls, so j only moves forward: O(n) overall.
RelativeErrors ComputeRelativeErrors(const std::vector<PosePair>& pairs, double segment_m) {
  RelativeErrors errors;
  const size_t n = pairs.size();
  size_t j = 0;
  for (size_t i = 0; i < n; ++i) {
    j = std::max(j, i + 1);
    while (j < n && pairs[j].truth_arc_m - pairs[i].truth_arc_m < segment_m) {
      ++j;
    }
    if (j == n) break;
    const SE2 T_truth_i_j = pairs[i].T_map_truth.inverse() * pairs[j].T_map_truth;
    const SE2 T_estimate_i_j = pairs[i].T_map_estimate.inverse() * pairs[j].T_map_estimate;
    errors.translation_m.push_back(
        (T_truth_i_j.translation() - T_estimate_i_j.translation()).norm());
    errors.yaw_rad.push_back(AngleDiff(T_estimate_i_j.yaw(), T_truth_i_j.yaw()));
  }
  return errors;
}

double Rms(const std::vector<double>& values) {
  if (values.empty()) return kNaN;
  double sum_sq = 0.0;
  for (double v : values) sum_sq += v * v;
  return std::sqrt(sum_sq / static_cast<double>(values.size()));
}

double Mean(const std::vector<double>& values) {
  if (values.empty()) return kNaN;
  double sum = 0.0;
  for (double v : values) sum += v;
  return sum / static_cast<double>(values.size());
}

}  // namespace

TrajectoryMetrics EvaluateTrajectory(const Trajectory& truth, const Trajectory& estimate,
                                     const TrajectoryMetricsOptions& options) {
  ValidateInputs(truth, options);
  const std::vector<PosePair> pairs = MatchPoses(truth, estimate);

  TrajectoryMetrics metrics;
  metrics.matched_poses = static_cast<int>(pairs.size());
  metrics.length_m = pairs.back().truth_arc_m - pairs.front().truth_arc_m;
  metrics.T_truth_estimate = options.align ? Alignment(pairs) : SE2();
  FillAbsoluteErrors(pairs, metrics.T_truth_estimate, &metrics);

  const RelativeErrors rpe = ComputeRelativeErrors(pairs, options.rpe_segment_m);
  metrics.rpe_trans_rmse_m = Rms(rpe.translation_m);
  metrics.rpe_yaw_rmse_rad = Rms(rpe.yaw_rad);

  const RelativeErrors drift = ComputeRelativeErrors(pairs, options.drift_segment_m);
  metrics.drift_per_100m_m = Mean(drift.translation_m);
  metrics.drift_percent = 100.0 * metrics.drift_per_100m_m / options.drift_segment_m;
  return metrics;
}

double AlignedPositionRmse(const std::map<int, SE2>& estimate, const std::map<int, SE2>& truth) {
  std::vector<Eigen::Vector2d> estimated, true_positions;
  for (const auto& [id, T] : estimate) {
    const auto it = truth.find(id);
    if (it == truth.end()) continue;
    estimated.push_back(T.translation());
    true_positions.push_back(it->second.translation());
  }
  if (estimated.size() < 2) {
    throw std::invalid_argument("AlignedPositionRmse: fewer than 2 poses match the truth");
  }
  const SE2 T_truth_estimate = AlignPointSets(estimated, true_positions);
  double sum = 0.0;
  for (size_t i = 0; i < estimated.size(); ++i) {
    sum += (T_truth_estimate * estimated[i] - true_positions[i]).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(estimated.size()));
}

}  // namespace parkslam::eval
