#include "parkslam/mapping/costs/angle.h"

#include <ceres/internal/eigen.h>
#include <ceres/jet.h>
#include <ceres/manifold_test_utils.h>
#include <gtest/gtest.h>

#include <Eigen/Core>

#include <array>
#include <cmath>

#include "parkslam/common/angles.h"

namespace parkslam::mapping {
namespace {

using Jet1 = ceres::Jet<double, 1>;

TEST(WrapAngleTest, MapsIntoHalfOpenIntervalAtTheEnds) {
  EXPECT_DOUBLE_EQ(WrapAngle(kPi), kPi);
  EXPECT_DOUBLE_EQ(WrapAngle(-kPi), kPi);
  EXPECT_DOUBLE_EQ(WrapAngle(0.0), 0.0);
  EXPECT_NEAR(WrapAngle(3.0 * kPi), kPi, 1e-12);
}

TEST(WrapAngleTest, JustAboveAndBelowPi) {
  EXPECT_NEAR(WrapAngle(kPi + 1e-6), -kPi + 1e-6, 1e-12);
  EXPECT_NEAR(WrapAngle(kPi - 1e-6), kPi - 1e-6, 1e-12);
  EXPECT_NEAR(WrapAngle(-kPi + 1e-6), -kPi + 1e-6, 1e-12);
  EXPECT_NEAR(WrapAngle(-kPi - 1e-6), kPi - 1e-6, 1e-12);
}

TEST(WrapAngleTest, AgreesWithNormalizeAngleOverSeveralTurns) {
  for (double a = -20.0; a <= 20.0; a += 0.01) {
    const double wrapped = WrapAngle(a);
    EXPECT_GT(wrapped, -kPi) << a;
    EXPECT_LE(wrapped, kPi) << a;
    EXPECT_NEAR(wrapped, NormalizeAngle(a), 1e-12) << a;
  }
}

TEST(WrapAngleTest, JetKeepsUnitDerivativeAcrossTheWrap) {
  for (const double a :
       {kPi - 1e-3, kPi + 1e-3, -kPi - 1e-3, -kPi + 1e-3, 7.0 * kPi + 0.1, -5.0 * kPi - 0.2, 0.3}) {
    const Jet1 wrapped = WrapAngle(Jet1(a, 0));
    EXPECT_NEAR(wrapped.a, NormalizeAngle(a), 1e-12) << a;
    EXPECT_DOUBLE_EQ(wrapped.v[0], 1.0) << a;
  }
}

TEST(Pose2ManifoldTest, PlusWrapsTheYaw) {
  const Pose2Manifold manifold;
  const std::array<double, 3> x = {1.0, -2.0, kPi - 0.1};
  const std::array<double, 3> delta = {0.5, 0.25, 0.3};
  std::array<double, 3> x_plus_delta{};
  ASSERT_TRUE(manifold.Plus(x.data(), delta.data(), x_plus_delta.data()));
  EXPECT_DOUBLE_EQ(x_plus_delta[0], 1.5);
  EXPECT_DOUBLE_EQ(x_plus_delta[1], -1.75);
  EXPECT_NEAR(x_plus_delta[2], -kPi + 0.2, 1e-12);
}

TEST(Pose2ManifoldTest, MinusTakesTheShortArcAcrossTheWrap) {
  const Pose2Manifold manifold;
  const std::array<double, 3> x = {1.0, 1.0, kPi - 0.1};
  const std::array<double, 3> y = {3.0, 0.0, -kPi + 0.1};
  std::array<double, 3> y_minus_x{};
  ASSERT_TRUE(manifold.Minus(y.data(), x.data(), y_minus_x.data()));
  EXPECT_DOUBLE_EQ(y_minus_x[0], 2.0);
  EXPECT_DOUBLE_EQ(y_minus_x[1], -1.0);
  EXPECT_NEAR(y_minus_x[2], 0.2, 1e-12);
}

TEST(Pose2ManifoldTest, PlusMinusRoundTripAcrossTheWrap) {
  const Pose2Manifold manifold;
  for (const double yaw : {kPi - 0.05, kPi, -kPi + 0.05, 0.0}) {
    for (const double d_yaw : {-0.3, -0.04, 0.04, 0.3}) {
      const std::array<double, 3> x = {2.0, -1.0, yaw};
      const std::array<double, 3> delta = {0.1, -0.2, d_yaw};
      std::array<double, 3> y{}, back{};
      ASSERT_TRUE(manifold.Plus(x.data(), delta.data(), y.data()));
      EXPECT_GT(y[2], -kPi);
      EXPECT_LE(y[2], kPi);
      ASSERT_TRUE(manifold.Minus(y.data(), x.data(), back.data()));
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(back[i], delta[i], 1e-12);
      // And x [+] (y [-] x) returns y.
      std::array<double, 3> y_again{};
      ASSERT_TRUE(manifold.Plus(x.data(), back.data(), y_again.data()));
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(y_again[i], y[i], 1e-12);
    }
  }
}

TEST(Pose2ManifoldTest, CeresManifoldInvariantsHoldNearTheWrap) {
  const Pose2Manifold manifold;
  ceres::Vector x(3), delta(3), y(3);
  x << 0.5, -1.5, kPi - 0.05;
  delta << 0.2, 0.1, 0.2;      // crosses +pi
  y << 1.0, 2.0, -kPi + 0.05;  // on the other side of the wrap
  const ceres::Vector zero = ceres::Vector::Zero(3);
  constexpr double kTolerance = 1e-9;
  EXPECT_THAT(manifold, ceres::XPlusZeroIsXAt(x, kTolerance));
  EXPECT_THAT(manifold, ceres::XMinusXIsZeroAt(x, kTolerance));
  EXPECT_THAT(manifold, ceres::MinusPlusIsIdentityAt(x, delta, kTolerance));
  EXPECT_THAT(manifold, ceres::MinusPlusIsIdentityAt(x, zero, kTolerance));
  EXPECT_THAT(manifold, ceres::PlusMinusIsIdentityAt(x, y, kTolerance));
  EXPECT_THAT(manifold, ceres::HasCorrectPlusJacobianAt(x, kTolerance));
  EXPECT_THAT(manifold, ceres::HasCorrectMinusJacobianAt(x, kTolerance));
  EXPECT_THAT(manifold, ceres::MinusPlusJacobianIsIdentityAt(x, kTolerance));
  EXPECT_THAT(manifold, ceres::HasCorrectRightMultiplyByPlusJacobianAt(x, kTolerance));
}

}  // namespace
}  // namespace parkslam::mapping
