#include "parkslam/sensor/sensor_log.h"

#include <gtest/gtest.h>

namespace parkslam {
namespace {

TEST(SensorLogSourceTest, MergesStreamsByTime) {
  SensorLog log;
  log.wheel_speeds = {{10, 1.0}, {30, 1.0}};
  log.imu_samples = {{5, 0, 0}, {20, 0, 0}, {30, 0, 0}};
  log.slot_frames = {{25, {}}};
  SensorLogSource source(log);
  std::vector<TimeNs> times;
  std::vector<std::size_t> kinds;
  while (auto event = source.Next()) {
    times.push_back(EventTime(*event));
    kinds.push_back(event->index());
  }
  EXPECT_EQ(times, (std::vector<TimeNs>{5, 10, 20, 25, 30, 30}));
  // At t = 30 the wheel speed (index 0) comes before the IMU (index 2).
  EXPECT_EQ(kinds[4], 0u);
  EXPECT_EQ(kinds[5], 2u);
}

TEST(SensorLogSourceTest, EmptyLogEndsAtOnce) {
  SensorLog log;
  SensorLogSource source(log);
  EXPECT_FALSE(source.Next().has_value());
}

}  // namespace
}  // namespace parkslam
