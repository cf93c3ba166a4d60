#include "parkslam/mapping/costs/corner_observation_factor.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/LU>

#include <memory>
#include <stdexcept>

#include "parkslam/common/angles.h"
#include "parkslam/common/random.h"
#include "parkslam/mapping/costs/cost_test_util.h"

namespace parkslam::mapping {
namespace {

using testing::JacobiansMatchNumeric;
using testing::Residuals;

TEST(CornerObservationFactorTest, CornerTwoMetresAheadOfPoseFacingPlusYIsExact) {
  // Pose at (3, 1) facing +y: the corner (3, 3) is 2 m straight ahead.
  const std::unique_ptr<ceres::CostFunction> cost(
      CornerObservationFactor::Create(Eigen::Vector2d(2.0, 0.0), Eigen::Matrix2d::Identity()));
  EXPECT_NEAR(Residuals(*cost, {{3.0, 1.0, kPi / 2}, {3.0, 3.0}}).norm(), 0.0, 1e-12);
}

TEST(CornerObservationFactorTest, ResidualByHandIsWhitenedVehicleFrameError) {
  // Measured (1.8, 0.1) with sigma 0.1 m: error (0.2, -0.1) -> (2, -1).
  const std::unique_ptr<ceres::CostFunction> cost(CornerObservationFactor::Create(
      Eigen::Vector2d(1.8, 0.1), 0.01 * Eigen::Matrix2d::Identity()));
  const Eigen::VectorXd r = Residuals(*cost, {{3.0, 1.0, kPi / 2}, {3.0, 3.0}});
  EXPECT_NEAR(r(0), 2.0, 1e-12);
  EXPECT_NEAR(r(1), -1.0, 1e-12);
}

TEST(CornerObservationFactorTest, CornerWestOfPoseFacingPlusYIsOnTheLeft) {
  // Facing +y, the map's -x is the vehicle's +y (left): (1, 1) is at (0, 2).
  const std::unique_ptr<ceres::CostFunction> cost(
      CornerObservationFactor::Create(Eigen::Vector2d::Zero(), Eigen::Matrix2d::Identity()));
  const Eigen::VectorXd r = Residuals(*cost, {{3.0, 1.0, kPi / 2}, {1.0, 1.0}});
  EXPECT_NEAR(r(0), 0.0, 1e-12);
  EXPECT_NEAR(r(1), 2.0, 1e-12);
}

TEST(CornerObservationFactorTest, JacobiansMatchNumericIncludingYawNearPi) {
  Random random(11);
  Eigen::Matrix2d covariance;
  covariance << 0.04, 0.015, 0.015, 0.0225;
  const std::unique_ptr<ceres::CostFunction> cost(
      CornerObservationFactor::Create(Eigen::Vector2d(3.0, -1.0), covariance));
  for (const double yaw : {kPi - 1e-4, -kPi + 1e-4, kPi, 1.1, -0.4}) {
    for (int trial = 0; trial < 4; ++trial) {
      const std::vector<double> pose = {random.Uniform(-20, 20), random.Uniform(-20, 20), yaw};
      const std::vector<double> corner = {random.Uniform(-20, 20), random.Uniform(-20, 20)};
      EXPECT_TRUE(JacobiansMatchNumeric(*cost, {pose, corner})) << yaw;
    }
  }
}

TEST(CornerObservationFactorTest, SquaredResidualIsTheMahalanobisDistance) {
  Eigen::Matrix2d covariance;
  covariance << 0.09, -0.05, -0.05, 0.04;
  const Eigen::Vector2d z(4.0, 1.0);
  const std::unique_ptr<ceres::CostFunction> cost(CornerObservationFactor::Create(z, covariance));
  // Pose at the origin facing +x: the vehicle frame is the map frame.
  const Eigen::Vector2d corner(4.3, 0.6);
  const Eigen::Vector2d e = corner - z;
  const double mahalanobis = e.dot(covariance.inverse() * e);
  const Eigen::VectorXd r = Residuals(*cost, {{0.0, 0.0, 0.0}, {corner.x(), corner.y()}});
  EXPECT_NEAR(0.5 * r.squaredNorm(), 0.5 * mahalanobis, 1e-10 * mahalanobis);
}

TEST(CornerObservationFactorTest, RejectsAnAsymmetricCovariance) {
  Eigen::Matrix2d covariance;
  covariance << 1.0, 0.5, 0.0, 1.0;
  EXPECT_THROW(CornerObservationFactor(Eigen::Vector2d::Zero(), covariance), std::invalid_argument);
}

}  // namespace
}  // namespace parkslam::mapping
