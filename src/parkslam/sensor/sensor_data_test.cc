#include "parkslam/sensor/sensor_data.h"

#include <gtest/gtest.h>

namespace parkslam {
namespace {

DigitReading Digit(char d, double p) { return DigitReading{{{d, p}}}; }

TEST(SlotIdReadingTest, FullReading) {
  const SlotIdReading id{{Digit('3', 0.9), Digit('8', 0.5)}};
  EXPECT_EQ(id.best(), "38");
  EXPECT_FALSE(id.partial());
  EXPECT_FALSE(id.empty());
  EXPECT_NEAR(id.confidence(), 0.45, 1e-12);
}

TEST(SlotIdReadingTest, PartialReadingMarksUnreadDigit) {
  const SlotIdReading id{{DigitReading{}, Digit('8', 0.7)}};
  EXPECT_EQ(id.best(), "?8");
  EXPECT_TRUE(id.partial());
  EXPECT_NEAR(id.confidence(), 0.7, 1e-12);
}

TEST(SlotIdReadingTest, EmptyReading) {
  const SlotIdReading id;
  EXPECT_TRUE(id.empty());
  EXPECT_EQ(id.best(), "");
  EXPECT_EQ(id.confidence(), 0.0);
  EXPECT_FALSE(id.partial());
}

TEST(SensorEventTest, EventTimeOfEachKind) {
  EXPECT_EQ(EventTime(WheelSpeed{5, 1.0}), 5);
  EXPECT_EQ(EventTime(ImuSample{7, 0.0, 0.0}), 7);
  EXPECT_EQ(EventTime(SlotObservationFrame{9, {}}), 9);
}

}  // namespace
}  // namespace parkslam
