#include "parkslam/common/se2.h"

#include <gtest/gtest.h>

namespace parkslam {
namespace {

TEST(SE2Test, ComposeThenInverseIsIdentity) {
  const SE2 T_a_b(1.5, -2.0, 0.7);
  const SE2 identity = T_a_b * T_a_b.inverse();
  EXPECT_NEAR(identity.x(), 0.0, 1e-12);
  EXPECT_NEAR(identity.y(), 0.0, 1e-12);
  EXPECT_NEAR(identity.yaw(), 0.0, 1e-12);
}

TEST(SE2Test, TransformsPointIntoParentFrame) {
  // Vehicle at (10, 5) facing +y: a point 2 m ahead lies at (10, 7).
  const SE2 T_map_vehicle(10.0, 5.0, kPi / 2);
  const Eigen::Vector2d p_map = T_map_vehicle * Eigen::Vector2d(2.0, 0.0);
  EXPECT_NEAR(p_map.x(), 10.0, 1e-12);
  EXPECT_NEAR(p_map.y(), 7.0, 1e-12);
}

TEST(SE2Test, CompositionMatchesMatrixProduct) {
  const SE2 a(1.0, 2.0, 0.3), b(-0.5, 4.0, -2.9);
  const Eigen::Matrix3d expected = a.matrix() * b.matrix();
  EXPECT_TRUE((a * b).matrix().isApprox(expected, 1e-12));
}

TEST(SE2Test, YawIsNormalizedOnConstruction) {
  EXPECT_NEAR(SE2(0, 0, 3 * kPi / 2).yaw(), -kPi / 2, 1e-12);
  EXPECT_NEAR(SE2(0, 0, -kPi).yaw(), kPi, 1e-12);
}

TEST(SE2Test, InterpolateTakesShorterArc) {
  const SE2 a(0, 0, kPi - 0.1), b(2, 0, -kPi + 0.1);
  const SE2 mid = Interpolate(a, b, 0.5);
  EXPECT_NEAR(mid.x(), 1.0, 1e-12);
  EXPECT_NEAR(std::abs(mid.yaw()), kPi, 1e-12);
}

}  // namespace
}  // namespace parkslam
