#include "parkslam/common/angles.h"

#include <gtest/gtest.h>

namespace parkslam {
namespace {

TEST(AnglesTest, NormalizeMapsIntoHalfOpenInterval) {
  EXPECT_DOUBLE_EQ(NormalizeAngle(kPi), kPi);
  EXPECT_DOUBLE_EQ(NormalizeAngle(-kPi), kPi);
  EXPECT_NEAR(NormalizeAngle(2 * kPi + 0.25), 0.25, 1e-12);
  EXPECT_NEAR(NormalizeAngle(-2 * kPi - 0.25), -0.25, 1e-12);
  EXPECT_NEAR(NormalizeAngle(7 * kPi), kPi, 1e-9);
}

TEST(AnglesTest, JustAboveAndBelowPi) {
  EXPECT_NEAR(NormalizeAngle(kPi + 1e-6), -kPi + 1e-6, 1e-12);
  EXPECT_NEAR(NormalizeAngle(kPi - 1e-6), kPi - 1e-6, 1e-12);
}

TEST(AnglesTest, AngleDiffWrapsAcrossPi) {
  EXPECT_NEAR(AngleDiff(-kPi + 0.1, kPi - 0.1), 0.2, 1e-12);
  EXPECT_NEAR(AngleDiff(0.1, -0.1), 0.2, 1e-12);
}

TEST(AnglesTest, DegreesRoundTrip) {
  EXPECT_NEAR(DegToRad(180.0), kPi, 1e-15);
  EXPECT_NEAR(RadToDeg(DegToRad(37.5)), 37.5, 1e-12);
}

}  // namespace
}  // namespace parkslam
