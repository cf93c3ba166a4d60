#include "parkslam/harness/dead_reckoning.h"

#include <stdexcept>

namespace parkslam::harness {

DeadReckoningResult RunDeadReckoning(SensorSource& source,
                                     const odometry::OdometryEkfOptions& ekf_options,
                                     const DeadReckoningOptions& options) {
  std::string error;
  if (!ekf_options.IsValid(&error)) throw std::invalid_argument(error);
  if (!(options.output_rate_hz > 0.0)) {
    throw std::invalid_argument("output_rate_hz must be positive");
  }
  odometry::OdometryEkf ekf(ekf_options);
  DeadReckoningResult result;
  const TimeNs period_ns = FromSeconds(1.0 / options.output_rate_hz);
  TimeNs next_output_ns = 0;
  auto record = [&](TimeNs t_ns) {
    ekf.PredictTo(t_ns);
    result.poses.push_back({t_ns, ekf.pose(), ekf.pose_covariance()});
  };

  while (const std::optional<SensorEvent> event = source.Next()) {
    const TimeNs t_ns = EventTime(*event);
    if (!ekf.initialized()) {
      if (options.initial_pose) {
        ekf.Initialize(t_ns, *options.initial_pose, options.initial_yaw_sigma_rad);
      } else if (const auto* imu = std::get_if<ImuSample>(&*event)) {
        ekf.InitializeFromHeading(t_ns, Eigen::Vector2d::Zero(), imu->heading_rad);
      } else {
        continue;  // nothing to anchor the yaw yet
      }
      next_output_ns = t_ns;
    }
    if (t_ns < ekf.time_ns()) {
      ++result.rejected_events;
      continue;
    }
    while (next_output_ns < t_ns) {
      record(next_output_ns);
      next_output_ns += period_ns;
    }
    ekf.Process(*event);
  }
  if (ekf.initialized() && (result.poses.empty() || result.poses.back().t_ns < ekf.time_ns())) {
    record(ekf.time_ns());
  }
  return result;
}

Trajectory ToTrajectory(const std::vector<TimedPoseWithCovariance>& poses) {
  Trajectory trajectory;
  trajectory.reserve(poses.size());
  for (const auto& p : poses) trajectory.push_back({p.t_ns, p.T_map_vehicle});
  return trajectory;
}

}  // namespace parkslam::harness
