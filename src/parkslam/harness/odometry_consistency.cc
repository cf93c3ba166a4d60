#include "parkslam/harness/odometry_consistency.h"

#include <algorithm>
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

}  // namespace parkslam::harness
