#include "parkslam/mapping/costs/tag_observation_factor.h"

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

TEST(TagObservationFactorTest, TagAheadFacingTheVehicleIsExact) {
  // Pose at the origin facing +y; a tag 5 m ahead whose normal points back at
  // the vehicle (map yaw -pi/2): in the vehicle frame at (5, 0), yaw pi.
  const std::unique_ptr<ceres::CostFunction> cost(TagObservationFactor::Create(
      Eigen::Vector2d(5.0, 0.0), kPi, Eigen::Matrix2d::Identity(), 0.1));
  const Eigen::VectorXd r = Residuals(*cost, {{0.0, 0.0, kPi / 2}, {0.0, 5.0, -kPi / 2}});
  EXPECT_NEAR(r.norm(), 0.0, 1e-12);
}

TEST(TagObservationFactorTest, YawResidualIsWrappedAndWhitened) {
  // Same geometry, measured yaw -pi + 0.05 (0.05 past pi): the error is
  // pi - (-pi + 0.05) = 2 pi - 0.05 -> -0.05 rad, over sigma 0.1 -> -0.5.
  // Position measured (5.2, -0.1) with sigma 0.2 m: error (-0.2, 0.1) -> (-1, 0.5).
  const std::unique_ptr<ceres::CostFunction> cost(TagObservationFactor::Create(
      Eigen::Vector2d(5.2, -0.1), -kPi + 0.05, 0.04 * Eigen::Matrix2d::Identity(), 0.1));
  const Eigen::VectorXd r = Residuals(*cost, {{0.0, 0.0, kPi / 2}, {0.0, 5.0, -kPi / 2}});
  EXPECT_NEAR(r(0), -1.0, 1e-12);
  EXPECT_NEAR(r(1), 0.5, 1e-12);
  EXPECT_NEAR(r(2), -0.5, 1e-12);
}

TEST(TagObservationFactorTest, JacobiansMatchNumericIncludingYawNearPi) {
  Random random(13);
  Eigen::Matrix2d covariance;
  covariance << 0.0625, 0.02, 0.02, 0.01;
  const std::unique_ptr<ceres::CostFunction> cost(
      TagObservationFactor::Create(Eigen::Vector2d(6.0, 1.0), 2.9, covariance, 0.05));
  for (const double yaw : {kPi - 1e-4, -kPi + 1e-4, kPi, 0.3, -1.7}) {
    for (int trial = 0; trial < 4; ++trial) {
      const std::vector<double> pose = {random.Uniform(-20, 20), random.Uniform(-20, 20), yaw};
      // Tag yaw near yaw + 2.9 so that the yaw residual stays away from +-pi.
      const std::vector<double> tag = {random.Uniform(-20, 20), random.Uniform(-20, 20),
                                       NormalizeAngle(yaw + 2.9 + random.Uniform(-0.3, 0.3))};
      EXPECT_TRUE(JacobiansMatchNumeric(*cost, {pose, tag})) << yaw;
    }
  }
}

TEST(TagObservationFactorTest, SquaredResidualIsTheBlockDiagonalMahalanobisDistance) {
  Eigen::Matrix2d position_covariance;
  position_covariance << 0.09, 0.03, 0.03, 0.02;
  const double yaw_sigma = 0.07;
  const std::unique_ptr<ceres::CostFunction> cost(
      TagObservationFactor::Create(Eigen::Vector2d(4.0, 0.0), 0.2, position_covariance, yaw_sigma));
  // Pose at the origin facing +x; tag at (4.2, -0.3) with yaw 0.25.
  const Eigen::Vector3d e(0.2, -0.3, 0.05);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  covariance.topLeftCorner<2, 2>() = position_covariance;
  covariance(2, 2) = yaw_sigma * yaw_sigma;
  const double mahalanobis = e.dot(covariance.inverse() * e);
  const Eigen::VectorXd r = Residuals(*cost, {{0.0, 0.0, 0.0}, {4.2, -0.3, 0.25}});
  EXPECT_NEAR(0.5 * r.squaredNorm(), 0.5 * mahalanobis, 1e-9 * mahalanobis);
}

TEST(TagObservationFactorTest, RejectsANonPositiveYawSigma) {
  EXPECT_THROW(TagObservationFactor(Eigen::Vector2d::Zero(), 0.0, Eigen::Matrix2d::Identity(), 0.0),
               std::invalid_argument);
}

}  // namespace
}  // namespace parkslam::mapping
