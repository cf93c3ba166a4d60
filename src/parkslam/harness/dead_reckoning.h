#ifndef PARKSLAM_HARNESS_DEAD_RECKONING_H_
#define PARKSLAM_HARNESS_DEAD_RECKONING_H_

// Glue between the sensor stream and the odometry EKF, shared by the CLI,
// the demo and the consistency tests. No I/O.

#include <optional>
#include <vector>

#include "parkslam/common/trajectory.h"
#include "parkslam/odometry/odometry_ekf.h"
#include "parkslam/sensor/sensor_log.h"

namespace parkslam::harness {

struct DeadReckoningOptions {
  double output_rate_hz = 50.0;
  // Known start pose in the map frame. Without it the trajectory starts at
  // the origin with the yaw of the first AHRS heading (the odometry frame:
  // origin at the start, axes along the map's).
  std::optional<SE2> initial_pose;
  double initial_yaw_sigma_rad = 0.01;
};

struct DeadReckoningResult {
  std::vector<TimedPoseWithCovariance> poses;
  int rejected_events = 0;  // older than the filter time
};

// Runs the EKF over the whole stream and samples its pose at output_rate_hz.
DeadReckoningResult RunDeadReckoning(SensorSource& source,
                                     const odometry::OdometryEkfOptions& ekf_options,
                                     const DeadReckoningOptions& options);

// The poses without covariance.
Trajectory ToTrajectory(const std::vector<TimedPoseWithCovariance>& poses);

}  // namespace parkslam::harness

#endif  // PARKSLAM_HARNESS_DEAD_RECKONING_H_
