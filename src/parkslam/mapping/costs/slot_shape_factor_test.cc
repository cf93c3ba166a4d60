#include "parkslam/mapping/costs/slot_shape_factor.h"

#include <gtest/gtest.h>

#include <Eigen/Core>

#include <cmath>
#include <memory>
#include <stdexcept>

#include "parkslam/common/angles.h"
#include "parkslam/common/random.h"
#include "parkslam/mapping/costs/cost_test_util.h"

namespace parkslam::mapping {
namespace {

using testing::Blocks;
using testing::JacobiansMatchNumeric;
using testing::Residuals;

constexpr double kWidthM = 2.5;
constexpr double kDepthM = 5.3;
constexpr double kAngleSigmaRad = 0.01;
constexpr double kLengthSigmaM = 0.1;

// Corners c0..c3 of a slot: entrance c0 -> c1 along entrance_yaw, sides at
// interior angle `angle` (counter-clockwise from the entrance) at c0.
Blocks Parallelogram(const Eigen::Vector2d& c0, double entrance_yaw, double angle, double width,
                     double depth) {
  const Eigen::Vector2d u(std::cos(entrance_yaw), std::sin(entrance_yaw));
  const Eigen::Vector2d v(std::cos(entrance_yaw + angle), std::sin(entrance_yaw + angle));
  const Eigen::Vector2d c1 = c0 + width * u;
  const Eigen::Vector2d c2 = c1 + depth * v;
  const Eigen::Vector2d c3 = c0 + depth * v;
  return {{c0.x(), c0.y()}, {c1.x(), c1.y()}, {c2.x(), c2.y()}, {c3.x(), c3.y()}};
}

std::unique_ptr<ceres::CostFunction> Factor(double angle) {
  return std::unique_ptr<ceres::CostFunction>(
      SlotShapeFactor::Create(angle, kWidthM, kDepthM, kAngleSigmaRad, kLengthSigmaM));
}

TEST(SlotShapeFactorTest, PerfectRectangleHasZeroResidual) {
  const auto cost = Factor(kPi / 2);
  // Several orientations, including an entrance pointing along -x (yaw pi).
  for (const double yaw : {0.0, 0.4, kPi / 2, kPi, -kPi + 0.01, -2.0}) {
    const Eigen::VectorXd r =
        Residuals(*cost, Parallelogram({12.0, -3.0}, yaw, kPi / 2, kWidthM, kDepthM));
    EXPECT_NEAR(r.norm(), 0.0, 1e-9) << yaw;
  }
}

TEST(SlotShapeFactorTest, PerfectSixtyDegreeParallelogramHasZeroResidual) {
  const auto cost = Factor(DegToRad(60.0));
  for (const double yaw : {0.0, 1.0, kPi - 0.01, -kPi / 2}) {
    const Eigen::VectorXd r =
        Residuals(*cost, Parallelogram({-4.0, 7.5}, yaw, DegToRad(60.0), kWidthM, kDepthM));
    EXPECT_NEAR(r.norm(), 0.0, 1e-9) << yaw;
  }
}

TEST(SlotShapeFactorTest, RectangleCheckedAsSixtyDegreeSlotHasAngleResiduals) {
  const auto cost = Factor(DegToRad(60.0));
  const Eigen::VectorXd r =
      Residuals(*cost, Parallelogram({0.0, 0.0}, 0.3, kPi / 2, kWidthM, kDepthM));
  // Interior angles are all 90 deg: +30 deg at c0 and c2 (expected 60),
  // -30 deg at c1 and c3 (expected 120). Lengths are right.
  const double thirty = DegToRad(30.0) / kAngleSigmaRad;
  EXPECT_NEAR(r(0), thirty, 1e-9);
  EXPECT_NEAR(r(1), -thirty, 1e-9);
  EXPECT_NEAR(r(2), thirty, 1e-9);
  EXPECT_NEAR(r(3), -thirty, 1e-9);
  for (int i = 4; i < 8; ++i) EXPECT_NEAR(r(i), 0.0, 1e-9);
}

TEST(SlotShapeFactorTest, WrongSizeGivesOnlyLengthResiduals) {
  const auto cost = Factor(kPi / 2);
  // A rectangle 2.7 x 5.0 against the 2.5 x 5.3 shape.
  const Eigen::VectorXd r = Residuals(*cost, Parallelogram({1.0, 2.0}, -0.8, kPi / 2, 2.7, 5.0));
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(r(i), 0.0, 1e-9);
  EXPECT_NEAR(r(4), 0.2 / kLengthSigmaM, 1e-9);   // entrance
  EXPECT_NEAR(r(5), 0.2 / kLengthSigmaM, 1e-9);   // back line
  EXPECT_NEAR(r(6), -0.3 / kLengthSigmaM, 1e-9);  // side at c0
  EXPECT_NEAR(r(7), -0.3 / kLengthSigmaM, 1e-9);  // side at c1
}

TEST(SlotShapeFactorTest, MovingOneFarCornerBreaksTheShape) {
  const auto cost = Factor(kPi / 2);
  Blocks corners = Parallelogram({0.0, 0.0}, 0.0, kPi / 2, kWidthM, kDepthM);
  corners[2][0] += 0.2;  // c2 slides sideways by 0.2 m
  const Eigen::VectorXd r = Residuals(*cost, corners);
  // The side c1-c2 leans outward by atan(0.2 / 5.3): the interior angle
  // opens by that much at c1 and closes by it at c2; c0 and c3 keep theirs.
  const double lean = std::atan(0.2 / kDepthM) / kAngleSigmaRad;
  EXPECT_NEAR(r(0), 0.0, 1e-9);
  EXPECT_NEAR(r(1), lean, 1e-9);
  EXPECT_NEAR(r(2), -lean, 1e-9);
  EXPECT_NEAR(r(3), 0.0, 1e-9);
  EXPECT_NEAR(r(4), 0.0, 1e-9);
  EXPECT_NEAR(r(5), 0.2 / kLengthSigmaM, 1e-9);
}

TEST(SlotShapeFactorTest, ClockwiseCornerOrderIsPenalized) {
  const auto cost = Factor(kPi / 2);
  // The mirror image of a perfect rectangle: same lengths, clockwise order.
  Blocks corners = Parallelogram({0.0, 0.0}, 0.0, kPi / 2, kWidthM, kDepthM);
  for (auto& c : corners) c[1] = -c[1];
  const Eigen::VectorXd r = Residuals(*cost, corners);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(std::abs(r(i)), kPi / kAngleSigmaRad, 1e-6) << i;
  }
  for (int i = 4; i < 8; ++i) EXPECT_NEAR(r(i), 0.0, 1e-9);
}

TEST(SlotShapeFactorTest, JacobiansMatchNumericAtPerturbedSlots) {
  Random random(17);
  for (const double angle : {kPi / 2, DegToRad(60.0)}) {
    const auto cost = Factor(angle);
    for (const double yaw : {kPi - 1e-3, -kPi + 1e-3, 0.2, 2.0}) {
      for (int trial = 0; trial < 3; ++trial) {
        Blocks corners = Parallelogram({random.Uniform(-30, 30), random.Uniform(-30, 30)}, yaw,
                                       angle, kWidthM, kDepthM);
        for (auto& c : corners) {
          c[0] += random.Uniform(-0.3, 0.3);
          c[1] += random.Uniform(-0.3, 0.3);
        }
        // Residuals are scaled by 1/sigma (up to 100); compare relatively.
        EXPECT_TRUE(JacobiansMatchNumeric(*cost, corners, 1e-6, 1e-5)) << angle << " " << yaw;
      }
    }
  }
}

TEST(SlotShapeFactorTest, RejectsAnAngleOutsideZeroToPi) {
  EXPECT_THROW(SlotShapeFactor(0.0, kWidthM, kDepthM, 0.01, 0.1), std::invalid_argument);
  EXPECT_THROW(SlotShapeFactor(kPi, kWidthM, kDepthM, 0.01, 0.1), std::invalid_argument);
  EXPECT_THROW(SlotShapeFactor(kPi / 2, kWidthM, kDepthM, 0.0, 0.1), std::invalid_argument);
}

}  // namespace
}  // namespace parkslam::mapping
