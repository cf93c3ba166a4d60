#ifndef PARKSLAM_COMMON_TRAJECTORY_H_
#define PARKSLAM_COMMON_TRAJECTORY_H_

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "parkslam/common/se2.h"
#include "parkslam/common/time.h"

namespace parkslam {

// One stamped planar pose of the vehicle in the map frame.
struct TimedPose {
  TimeNs t_ns = 0;
  SE2 T_map_vehicle;
};

using Trajectory = std::vector<TimedPose>;

// A stamped pose with its covariance over (x_m, y_m, yaw_rad).
struct TimedPoseWithCovariance {
  TimeNs t_ns = 0;
  SE2 T_map_vehicle;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

// The pose at t_ns, interpolated between the two stamped poses around it.
// Empty outside [front, back] or for an empty trajectory. The trajectory must
// be sorted by time.
std::optional<SE2> PoseAt(const Trajectory& trajectory, TimeNs t_ns);

// The trajectory moved into another frame: each pose T_a_vehicle becomes
// T_b_a * T_a_vehicle.
Trajectory Transformed(const SE2& T_b_a, const Trajectory& trajectory_a);

// Appends `pose`, or replaces the last pose when it has the same time (the
// slots and tags of one camera frame share its time; the later estimate,
// which has used both, is kept). True when it appended.
bool AppendOrReplaceLast(Trajectory* trajectory, const TimedPose& pose);

// Length of the path through the trajectory's positions, in metres.
double PathLength(const Trajectory& trajectory);

}  // namespace parkslam

#endif  // PARKSLAM_COMMON_TRAJECTORY_H_
