#ifndef PARKSLAM_SENSOR_SENSOR_LOG_H_
#define PARKSLAM_SENSOR_SENSOR_LOG_H_

#include <cstddef>
#include <optional>
#include <vector>

#include "parkslam/sensor/sensor_data.h"

namespace parkslam {

// A recording: one time-sorted vector per sensor.
struct SensorLog {
  std::vector<WheelSpeed> wheel_speeds;
  std::vector<SteeringAngle> steering_angles;
  std::vector<ImuSample> imu_samples;
  std::vector<SlotObservationFrame> slot_frames;
  std::vector<TagObservationFrame> tag_frames;
};

// A source of sensor events in non-decreasing time order. Live simulation,
// a recorded dataset and a real vehicle all look alike downstream.
class SensorSource {
 public:
  virtual ~SensorSource() = default;
  // The next event, or nothing at the end of the stream.
  virtual std::optional<SensorEvent> Next() = 0;
};

// Replays a SensorLog, merging its vectors by time. Ties go in the order
// wheel speed, steering, IMU, slots, tags. The log must outlive the source.
class SensorLogSource final : public SensorSource {
 public:
  explicit SensorLogSource(const SensorLog& log) : log_(log) {}
  std::optional<SensorEvent> Next() override;

 private:
  const SensorLog& log_;
  std::size_t next_wheel_ = 0, next_steering_ = 0, next_imu_ = 0, next_slots_ = 0, next_tags_ = 0;
};

}  // namespace parkslam

#endif  // PARKSLAM_SENSOR_SENSOR_LOG_H_
