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

// What a landmark filter takes from the dead reckoning is its motion over a
// short window, not its pose since the start: the filter's stochastic clone
// (OdometryEkf::MotionSinceClone) gives that motion with its covariance.
// Over `runs` simulations each drive is cut into windows of every length in
// windows_s; each window's motion error (in the frame at its start) is
// scored against that covariance. The scale error of the wheel, drawn once
// per drive, makes windows of one drive correlated, so the mean is a figure
// to compare with the ideal, not a test against a strict band. The windows
// where the car turns (|yaw change| > turn_threshold_rad) are scored apart:
// there the bicycle model carries the yaw.
struct RelativeOdometryConsistency {
  double window_s = 0.0;
  int windows = 0;
  int turning_windows = 0;
  double mean_nees = 0.0;           // 3 dof (x, y, yaw); 3 is ideal
  double mean_position_nees = 0.0;  // 2 dof, its own 2x2 block; 2 is ideal
  double mean_yaw_nees = 0.0;       // 1 dof; 1 is ideal
  double mean_turning_nees = 0.0;   // 3 dof, turning windows only
  double mean_turning_yaw_nees = 0.0;
  // Share of windows whose 3-dof NEES lies inside the one-window 95 % band.
  double share_inside_window_band = 0.0;
};

// One result per entry of windows_s, in its order; each drive is simulated
// once for all of them.
std::vector<RelativeOdometryConsistency> EvaluateRelativeOdometryConsistency(
    const sim::ScenarioConfig& scenario, int runs, std::uint64_t first_seed,
    const std::vector<double>& windows_s, double turn_threshold_rad = 0.2,
    const std::function<void(int done, int total)>& on_run_done = {});

}  // namespace parkslam::harness

#endif  // PARKSLAM_HARNESS_ODOMETRY_CONSISTENCY_H_
