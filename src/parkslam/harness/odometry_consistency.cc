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

namespace {

// Sums of one window length's scores, turned into means by Result().
struct WindowScores {
  RelativeOdometryConsistency result;
  double sum = 0.0, sum_position = 0.0, sum_yaw = 0.0, sum_turning = 0.0, sum_turning_yaw = 0.0;
  int inside = 0;

  void Add(const Eigen::Vector3d& error, const Eigen::Matrix3d& covariance, bool turning,
           const eval::NeesBand& band) {
    const double nees = eval::Nees(error, covariance);
    const Eigen::Matrix2d position_covariance = covariance.topLeftCorner<2, 2>();
    const double position_nees =
        error.head<2>().dot(position_covariance.inverse() * error.head<2>());
    const double yaw_nees = error[2] * error[2] / covariance(2, 2);
    ++result.windows;
    sum += nees;
    sum_position += position_nees;
    sum_yaw += yaw_nees;
    inside += nees >= band.lower && nees <= band.upper;
    if (turning) {
      ++result.turning_windows;
      sum_turning += nees;
      sum_turning_yaw += yaw_nees;
    }
  }

  RelativeOdometryConsistency Result() const {
    RelativeOdometryConsistency r = result;
    if (r.windows > 0) {
      r.mean_nees = sum / r.windows;
      r.mean_position_nees = sum_position / r.windows;
      r.mean_yaw_nees = sum_yaw / r.windows;
      r.share_inside_window_band = static_cast<double>(inside) / r.windows;
    }
    if (r.turning_windows > 0) {
      r.mean_turning_nees = sum_turning / r.turning_windows;
      r.mean_turning_yaw_nees = sum_turning_yaw / r.turning_windows;
    }
    return r;
  }
};

// Runs the filter over one drive, cloning every window_ns, and scores each
// window's motion against the truth's.
void ScoreWindows(const sim::Simulation& sim, const Trajectory& truth,
                  const odometry::OdometryEkfOptions& ekf_options, TimeNs window_ns,
                  double turn_threshold_rad, const eval::NeesBand& band, WindowScores* scores) {
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
    scores->Add(error, motion.covariance, std::abs(true_motion.yaw()) > turn_threshold_rad, band);
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
}

}  // namespace

std::vector<RelativeOdometryConsistency> EvaluateRelativeOdometryConsistency(
    const sim::ScenarioConfig& scenario, int runs, std::uint64_t first_seed,
    const std::vector<double>& windows_s, double turn_threshold_rad,
    const std::function<void(int, int)>& on_run_done) {
  if (runs < 1) throw std::invalid_argument("runs must be at least 1");
  for (const double window_s : windows_s) {
    if (!(window_s > 0.0)) throw std::invalid_argument("window_s must be positive");
  }
  const odometry::OdometryEkfOptions ekf_options =
      odometry::EkfOptionsFromSpec(scenario.sensors.odometry, scenario.vehicle);
  const eval::NeesBand window_band = eval::AverageNeesBand(3, 1);
  std::vector<WindowScores> scores(windows_s.size());
  for (int run = 0; run < runs; ++run) {
    const sim::Simulation sim = sim::Simulate(scenario, first_seed + run);
    const Trajectory truth = sim::GroundTruthTrajectory(sim);
    for (size_t w = 0; w < windows_s.size(); ++w) {
      ScoreWindows(sim, truth, ekf_options, FromSeconds(windows_s[w]), turn_threshold_rad,
                   window_band, &scores[w]);
    }
    if (on_run_done) on_run_done(run + 1, runs);
  }
  std::vector<RelativeOdometryConsistency> results;
  for (size_t w = 0; w < windows_s.size(); ++w) {
    results.push_back(scores[w].Result());
    results.back().window_s = windows_s[w];
  }
  return results;
}

}  // namespace parkslam::harness
