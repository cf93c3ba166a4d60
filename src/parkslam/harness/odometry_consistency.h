#ifndef PARKSLAM_HARNESS_ODOMETRY_CONSISTENCY_H_
#define PARKSLAM_HARNESS_ODOMETRY_CONSISTENCY_H_

#include <cstdint>
#include <functional>
#include <vector>

#include "parkslam/sim/scenario_config.h"

namespace parkslam::harness {

// Monte-Carlo consistency of the dead-reckoning EKF on a scenario: `runs`
// simulations with seeds first_seed, first_seed + 1, ...; at every sample
// time the pose NEES (3 dof: x, y, yaw in the odometry frame) is averaged
// over the runs (ANEES) and compared with the two-sided 95 % chi-square band
// of that average (Bar-Shalom, Li, Kirubarajan, "Estimation with
// Applications to Tracking and Navigation", 5.4.2).
struct OdometryConsistency {
  int runs = 0;
  std::vector<double> times_s;  // sample times from the start
  std::vector<double> anees;    // average NEES at each time
  double band_lower = 0.0, band_upper = 0.0;
  double share_inside_band = 0.0;  // of the sample times
  double mean_anees = 0.0;         // over time (3 is ideal)
};

OdometryConsistency EvaluateOdometryConsistency(
    const sim::ScenarioConfig& scenario, int runs, std::uint64_t first_seed,
    double sample_period_s = 1.0, const std::function<void(int done, int total)>& on_run_done = {});

}  // namespace parkslam::harness

#endif  // PARKSLAM_HARNESS_ODOMETRY_CONSISTENCY_H_
