#include "parkslam/mapping/costs/prior_factor.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/LU>

#include <memory>
#include <stdexcept>

#include "parkslam/common/angles.h"
#include "parkslam/common/random.h"
#include "parkslam/common/se2.h"
#include "parkslam/mapping/costs/cost_test_util.h"

namespace parkslam::mapping {
namespace {

using testing::Jacobians;
using testing::JacobiansMatchNumeric;
using testing::Residuals;

TEST(PosePriorFactorTest, ResidualByHandAcrossTheWrap) {
  // Prior yaw pi - 0.05, pose yaw -pi + 0.05: 0.1 rad apart across pi.
  const Eigen::Matrix3d covariance = Eigen::Vector3d(0.04, 0.01, 0.0004).asDiagonal();
  const std::unique_ptr<ceres::CostFunction> cost(
      PosePriorFactor::Create(SE2(1.0, 2.0, kPi - 0.05), covariance));
  const Eigen::VectorXd r = Residuals(*cost, {{1.4, 1.9, -kPi + 0.05}});
  EXPECT_NEAR(r(0), 0.4 / 0.2, 1e-12);
  EXPECT_NEAR(r(1), -0.1 / 0.1, 1e-12);
  EXPECT_NEAR(r(2), 0.1 / 0.02, 1e-9);
}

TEST(PosePriorFactorTest, SquaredResidualIsTheMahalanobisDistance) {
  Eigen::Matrix3d covariance;
  covariance << 0.5, 0.2, 0.01,  //
      0.2, 0.3, 0.0,             //
      0.01, 0.0, 0.02;
  const std::unique_ptr<ceres::CostFunction> cost(
      PosePriorFactor::Create(SE2(0.0, 0.0, 0.0), covariance));
  const Eigen::Vector3d e(0.3, -0.6, 0.1);
  const double mahalanobis = e.dot(covariance.inverse() * e);
  const Eigen::VectorXd r = Residuals(*cost, {{e(0), e(1), e(2)}});
  EXPECT_NEAR(0.5 * r.squaredNorm(), 0.5 * mahalanobis, 1e-10 * mahalanobis);
}

TEST(PosePriorFactorTest, JacobianMatchesNumericIncludingYawNearPi) {
  Random random(19);
  Eigen::Matrix3d covariance;
  covariance << 0.5, 0.2, 0.01,  //
      0.2, 0.3, 0.0,             //
      0.01, 0.0, 0.02;
  const std::unique_ptr<ceres::CostFunction> cost(
      PosePriorFactor::Create(SE2(3.0, -2.0, kPi - 0.01), covariance));
  for (const double yaw : {kPi - 1e-4, -kPi + 1e-4, kPi, 2.5}) {
    const std::vector<double> pose = {random.Uniform(-5, 5), random.Uniform(-5, 5), yaw};
    EXPECT_TRUE(JacobiansMatchNumeric(*cost, {pose})) << yaw;
  }
}

TEST(PointPriorFactorTest, ResidualIsOffsetOverSigma) {
  const std::unique_ptr<ceres::CostFunction> cost(
      PointPriorFactor::Create(Eigen::Vector2d(5.0, -1.0), 2.0));
  const Eigen::VectorXd r = Residuals(*cost, {{6.0, -4.0}});
  EXPECT_NEAR(r(0), 0.5, 1e-12);
  EXPECT_NEAR(r(1), -1.5, 1e-12);
}

TEST(PointPriorFactorTest, JacobianIsIdentityOverSigma) {
  const std::unique_ptr<ceres::CostFunction> cost(
      PointPriorFactor::Create(Eigen::Vector2d(5.0, -1.0), 2.0));
  const auto jacobians = Jacobians(*cost, {{6.0, -4.0}});
  EXPECT_TRUE(jacobians[0].isApprox(0.5 * Eigen::Matrix2d::Identity()));
  EXPECT_TRUE(JacobiansMatchNumeric(*cost, {{6.0, -4.0}}));
}

TEST(PointPriorFactorTest, RejectsANonPositiveSigma) {
  EXPECT_THROW(PointPriorFactor(Eigen::Vector2d::Zero(), 0.0), std::invalid_argument);
  EXPECT_THROW(PointPriorFactor(Eigen::Vector2d::Zero(), -1.0), std::invalid_argument);
}

TEST(ScalarPriorFactorTest, ResidualAndJacobianAreOffsetAndOneOverSigma) {
  const std::unique_ptr<ceres::CostFunction> cost(ScalarPriorFactor::Create(0.001, 0.003));
  const Eigen::VectorXd r = Residuals(*cost, {{0.007}});
  EXPECT_NEAR(r(0), 2.0, 1e-12);
  const auto jacobians = Jacobians(*cost, {{0.007}});
  EXPECT_NEAR(jacobians[0](0, 0), 1.0 / 0.003, 1e-9);
  EXPECT_THROW(ScalarPriorFactor(0.0, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace parkslam::mapping
