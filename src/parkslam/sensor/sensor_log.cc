#include "parkslam/sensor/sensor_log.h"

#include <limits>

namespace parkslam {
namespace {

template <typename T>
TimeNs HeadTime(const std::vector<T>& v, std::size_t next) {
  return next < v.size() ? v[next].t_ns : std::numeric_limits<TimeNs>::max();
}

}  // namespace

std::optional<SensorEvent> SensorLogSource::Next() {
  const TimeNs times[] = {
      HeadTime(log_.wheel_speeds, next_wheel_), HeadTime(log_.steering_angles, next_steering_),
      HeadTime(log_.imu_samples, next_imu_), HeadTime(log_.slot_frames, next_slots_),
      HeadTime(log_.tag_frames, next_tags_)};
  int best = 0;
  for (int i = 1; i < 5; ++i) {
    if (times[i] < times[best]) best = i;
  }
  if (times[best] == std::numeric_limits<TimeNs>::max()) return std::nullopt;
  switch (best) {
    case 0:
      return log_.wheel_speeds[next_wheel_++];
    case 1:
      return log_.steering_angles[next_steering_++];
    case 2:
      return log_.imu_samples[next_imu_++];
    case 3:
      return log_.slot_frames[next_slots_++];
    default:
      return log_.tag_frames[next_tags_++];
  }
}

}  // namespace parkslam
