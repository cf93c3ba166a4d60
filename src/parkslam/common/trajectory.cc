#include "parkslam/common/trajectory.h"

#include <algorithm>

namespace parkslam {

std::optional<SE2> PoseAt(const Trajectory& trajectory, TimeNs t_ns) {
  if (trajectory.empty() || t_ns < trajectory.front().t_ns || t_ns > trajectory.back().t_ns) {
    return std::nullopt;
  }
  const auto after =
      std::lower_bound(trajectory.begin(), trajectory.end(), t_ns,
                       [](const TimedPose& pose, TimeNs t) { return pose.t_ns < t; });
  if (after->t_ns == t_ns || after == trajectory.begin()) {
    return after->T_map_vehicle;
  }
  const auto before = after - 1;
  const double fraction =
      static_cast<double>(t_ns - before->t_ns) / static_cast<double>(after->t_ns - before->t_ns);
  return Interpolate(before->T_map_vehicle, after->T_map_vehicle, fraction);
}

Trajectory Transformed(const SE2& T_b_a, const Trajectory& trajectory_a) {
  Trajectory trajectory_b;
  trajectory_b.reserve(trajectory_a.size());
  for (const TimedPose& p : trajectory_a) trajectory_b.push_back({p.t_ns, T_b_a * p.T_map_vehicle});
  return trajectory_b;
}

double PathLength(const Trajectory& trajectory) {
  double length_m = 0.0;
  for (size_t i = 1; i < trajectory.size(); ++i) {
    length_m +=
        (trajectory[i].T_map_vehicle.translation() - trajectory[i - 1].T_map_vehicle.translation())
            .norm();
  }
  return length_m;
}

bool AppendOrReplaceLast(Trajectory* trajectory, const TimedPose& pose) {
  if (!trajectory->empty() && trajectory->back().t_ns == pose.t_ns) {
    trajectory->back() = pose;
    return false;
  }
  trajectory->push_back(pose);
  return true;
}

}  // namespace parkslam
