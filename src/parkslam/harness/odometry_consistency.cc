#include "parkslam/harness/odometry_consistency.h"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "parkslam/common/angles.h"
#include "parkslam/eval/consistency.h"
#include "parkslam/harness/dead_reckoning.h"
#include "parkslam/sim/simulator.h"

namespace parkslam::harness {

OdometryConsistency EvaluateOdometryConsistency(const sim::ScenarioConfig& scenario, int runs,
                                                std::uint64_t first_seed, double sample_period_s,
                                                const std::function<void(int, int)>& on_run_done) {
  if (runs < 1) throw std::invalid_argument("runs must be at least 1");
  OdometryConsistency result;
  result.runs = runs;
  std::vector<double> nees_sum;
  std::vector<int> nees_count;
  const odometry::OdometryEkfOptions ekf_options =
      odometry::EkfOptionsFromSpec(scenario.sensors.odometry, scenario.vehicle);
  DeadReckoningOptions dr_options;
  dr_options.output_rate_hz = 1.0 / sample_period_s;

  for (int run = 0; run < runs; ++run) {
    const sim::Simulation sim = sim::Simulate(scenario, first_seed + run);
    const Trajectory truth = sim::GroundTruthTrajectory(sim);
    SensorLogSource source(sim.log);
    const DeadReckoningResult dr = RunDeadReckoning(source, ekf_options, dr_options);
    // The odometry frame starts at the first pose's position, axes along
    // the map's (the yaw comes from the AHRS heading).
    const Eigen::Vector2d p0 = PoseAt(truth, dr.poses.front().t_ns)->translation();
    for (size_t k = 0; k < dr.poses.size(); ++k) {
      const auto& est = dr.poses[k];
      const std::optional<SE2> true_pose = PoseAt(truth, est.t_ns);
      if (!true_pose) continue;
      Eigen::Vector3d error;
      error.head<2>() = est.T_map_vehicle.translation() - (true_pose->translation() - p0);
      error[2] = AngleDiff(est.T_map_vehicle.yaw(), true_pose->yaw());
      if (k >= nees_sum.size()) {
        nees_sum.resize(k + 1, 0.0);
        nees_count.resize(k + 1, 0);
      }
      nees_sum[k] += eval::Nees(error, est.covariance);
      ++nees_count[k];
    }
    if (on_run_done) on_run_done(run + 1, runs);
  }
  const eval::NeesBand band = eval::AverageNeesBand(3, runs);
  result.band_lower = band.lower;
  result.band_upper = band.upper;
  int inside = 0;
  double total = 0.0;
  // Only times every run reached (drives may differ by a few samples).
  for (size_t k = 0; k < nees_sum.size(); ++k) {
    if (nees_count[k] != runs) continue;
    const double anees = nees_sum[k] / runs;
    result.times_s.push_back(static_cast<double>(k) * sample_period_s);
    result.anees.push_back(anees);
    inside += anees >= band.lower && anees <= band.upper;
    total += anees;
  }
  if (!result.anees.empty()) {
    result.share_inside_band = static_cast<double>(inside) / result.anees.size();
    result.mean_anees = total / result.anees.size();
  }
  return result;
}

RelativeOdometryConsistency EvaluateRelativeOdometryConsistency(
    const sim::ScenarioConfig& scenario, int runs, std::uint64_t first_seed, double window_s,
    double turn_threshold_rad, const std::function<void(int, int)>& on_run_done) {
  if (runs < 1) throw std::invalid_argument("runs must be at least 1");
  if (!(window_s > 0.0)) throw std::invalid_argument("window_s must be positive");
  const odometry::OdometryEkfOptions ekf_options =
      odometry::EkfOptionsFromSpec(scenario.sensors.odometry, scenario.vehicle);
  const eval::NeesBand window_band = eval::AverageNeesBand(3, 1);
  RelativeOdometryConsistency result;
  double sum = 0.0, sum_position = 0.0, sum_yaw = 0.0, sum_turning = 0.0, sum_turning_yaw = 0.0;
  int inside = 0;
  const TimeNs window_ns = FromSeconds(window_s);
  for (int run = 0; run < runs; ++run) {
    const sim::Simulation sim = sim::Simulate(scenario, first_seed + run);
    const Trajectory truth = sim::GroundTruthTrajectory(sim);
    SensorLogSource source(sim.log);
    odometry::OdometryEkf ekf(ekf_options);
    TimeNs window_start_ns = 0;
    auto score = [&](TimeNs t_ns) {
      ekf.PredictTo(t_ns);
      const std::optional<SE2> start = PoseAt(truth, window_start_ns);
      const std::optional<SE2> end = PoseAt(truth, t_ns);
      const odometry::OdometryEkf::RelativeMotion motion = ekf.MotionSinceClone();
      ekf.ClonePose();
      window_start_ns = t_ns;
      if (!start || !end) return;
      const SE2 true_motion = start->inverse() * *end;
      Eigen::Vector3d error;
      error.head<2>() = motion.T_clone_now.translation() - true_motion.translation();
      error[2] = AngleDiff(motion.T_clone_now.yaw(), true_motion.yaw());
      const double nees = eval::Nees(error, motion.covariance);
      const Eigen::Matrix2d position_covariance = motion.covariance.topLeftCorner<2, 2>();
      const double position_nees =
          error.head<2>().dot(position_covariance.inverse() * error.head<2>());
      const double yaw_nees = error[2] * error[2] / motion.covariance(2, 2);
      ++result.windows;
      sum += nees;
      sum_position += position_nees;
      sum_yaw += yaw_nees;
      inside += nees >= window_band.lower && nees <= window_band.upper;
      if (std::abs(true_motion.yaw()) > turn_threshold_rad) {
        ++result.turning_windows;
        sum_turning += nees;
        sum_turning_yaw += yaw_nees;
      }
    };
    while (const std::optional<SensorEvent> event = source.Next()) {
      const TimeNs t_ns = EventTime(*event);
      if (!ekf.initialized()) {
        const std::optional<SE2> start = PoseAt(truth, t_ns);
        if (!start) continue;
        ekf.Initialize(t_ns, *start, 0.01);
        window_start_ns = t_ns;
      }
      if (t_ns >= window_start_ns + window_ns) score(window_start_ns + window_ns);
      ekf.Process(*event);
    }
    if (on_run_done) on_run_done(run + 1, runs);
  }
  if (result.windows > 0) {
    result.mean_nees = sum / result.windows;
    result.mean_position_nees = sum_position / result.windows;
    result.mean_yaw_nees = sum_yaw / result.windows;
    result.share_inside_window_band = static_cast<double>(inside) / result.windows;
  }
  if (result.turning_windows > 0) {
    result.mean_turning_nees = sum_turning / result.turning_windows;
    result.mean_turning_yaw_nees = sum_turning_yaw / result.turning_windows;
  }
  return result;
}

}  // namespace parkslam::harness
