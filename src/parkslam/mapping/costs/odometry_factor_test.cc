#include "parkslam/mapping/costs/odometry_factor.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
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

using testing::Blocks;
using testing::JacobiansMatchNumeric;
using testing::Residuals;

std::vector<double> Block(const SE2& pose) { return {pose.x(), pose.y(), pose.yaw()}; }

TEST(OdometryFactorTest, ZeroResidualAtTheMeasuredRelativePose) {
  const SE2 T_map_a(4.0, -3.0, kPi - 0.02);
  const SE2 T_a_b(1.2, 0.3, 0.15);  // b ends up across the wrap at yaw ~ -pi
  const SE2 T_map_b = T_map_a * T_a_b;
  ASSERT_LT(T_map_b.yaw(), 0.0);
  const std::unique_ptr<ceres::CostFunction> cost(
      OdometryFactor::Create(T_a_b, Eigen::Matrix3d::Identity()));
  const Eigen::VectorXd r = Residuals(*cost, {Block(T_map_a), Block(T_map_b), {0.0}});
  EXPECT_NEAR(r.norm(), 0.0, 1e-12);
}

TEST(OdometryFactorTest, ResidualByHandForPoseFacingPlusY) {
  // a at (1, 2) facing +y; b 2 m further along +y, turned by 0.1 rad. In a's
  // frame b is at (2, 0). Measured (1.5, 0.2, 0.05); sigmas 0.5 m, 0.5 m, 0.1 rad.
  const Eigen::Matrix3d covariance = Eigen::Vector3d(0.25, 0.25, 0.01).asDiagonal();
  const std::unique_ptr<ceres::CostFunction> cost(
      OdometryFactor::Create(SE2(1.5, 0.2, 0.05), covariance));
  const Eigen::VectorXd r =
      Residuals(*cost, {{1.0, 2.0, kPi / 2}, {1.0, 4.0, kPi / 2 + 0.1}, {0.0}});
  EXPECT_NEAR(r(0), (2.0 - 1.5) / 0.5, 1e-12);
  EXPECT_NEAR(r(1), (0.0 - 0.2) / 0.5, 1e-12);
  EXPECT_NEAR(r(2), (0.1 - 0.05) / 0.1, 1e-12);
}

TEST(OdometryFactorTest, YawResidualIsWrappedAcrossPi) {
  // yaw_b - yaw_a = (-pi + 0.1) - (pi - 0.1) = -2 pi + 0.2 ~ 0.2; measured 0.1.
  const std::unique_ptr<ceres::CostFunction> cost(
      OdometryFactor::Create(SE2(0.0, 0.0, 0.1), Eigen::Matrix3d::Identity()));
  const Eigen::VectorXd r =
      Residuals(*cost, {{0.0, 0.0, kPi - 0.1}, {0.0, 0.0, -kPi + 0.1}, {0.0}});
  EXPECT_NEAR(r(2), 0.1, 1e-12);
}

TEST(OdometryFactorTest, JacobiansMatchNumericIncludingYawNearPi) {
  Random random(7);
  Eigen::Matrix3d covariance;
  covariance << 0.04, 0.01, 0.002,  //
      0.01, 0.09, -0.003,           //
      0.002, -0.003, 0.01;
  const std::unique_ptr<ceres::CostFunction> cost(
      OdometryFactor::Create(SE2(1.0, 0.2, -0.3), covariance));
  const double yaws[] = {kPi - 1e-4, -kPi + 1e-4, kPi, 0.7, -2.0};
  for (const double yaw_a : yaws) {
    for (int trial = 0; trial < 4; ++trial) {
      const std::vector<double> a = {random.Uniform(-10, 10), random.Uniform(-10, 10), yaw_a};
      const std::vector<double> b = {random.Uniform(-10, 10), random.Uniform(-10, 10),
                                     NormalizeAngle(yaw_a + random.Uniform(-0.5, 0.5))};
      EXPECT_TRUE(JacobiansMatchNumeric(*cost, {a, b, {random.Uniform(-0.01, 0.01)}}))
          << "yaw_a " << yaw_a;
    }
  }
}

TEST(OdometryFactorTest, SquaredResidualIsTheMahalanobisDistance) {
  Eigen::Matrix3d covariance;       // strongly non-isotropic, correlated
  covariance << 0.09, 0.05, 0.004,  //
      0.05, 0.04, -0.002,           //
      0.004, -0.002, 0.0025;
  const SE2 measured(2.0, 0.1, 0.05);
  const std::unique_ptr<ceres::CostFunction> cost(OdometryFactor::Create(measured, covariance));
  const std::vector<double> a = {1.0, -1.0, 0.4};
  const std::vector<double> b = {2.5, 0.9, 0.6};
  // e by hand: R(yaw_a)^T (t_b - t_a) - t_ab, yaw_b - yaw_a - yaw_ab.
  const Eigen::Vector2d relative =
      SE2(a[0], a[1], a[2]).rotation().transpose() * Eigen::Vector2d(b[0] - a[0], b[1] - a[1]);
  const Eigen::Vector3d e(relative.x() - 2.0, relative.y() - 0.1, b[2] - a[2] - 0.05);
  const double mahalanobis = e.dot(covariance.inverse() * e);
  const Eigen::VectorXd r = Residuals(*cost, {a, b, {0.0}});
  EXPECT_NEAR(0.5 * r.squaredNorm(), 0.5 * mahalanobis, 1e-10 * mahalanobis);
  // The lower factor (the trap of DESIGN.md section 4) would give another value.
  const Eigen::Matrix3d lower = covariance.inverse().llt().matrixL();
  EXPECT_GT(std::abs((lower * e).squaredNorm() - mahalanobis), 0.01 * mahalanobis);
}

// The wheel reads (1 + s) times the speed and the dead reckoning took s_o
// for it: the car moved (1 - (s - s_o)) times the measured translation.
TEST(OdometryFactorTest, TheWheelScaleErrorShortensTheMeasuredTranslation) {
  const std::unique_ptr<ceres::CostFunction> cost(
      OdometryFactor::Create(SE2(2.0, 0.0, 0.0), Eigen::Matrix3d::Identity(), 0.002));
  // s = 0.012: the odometry's 2 m were 2 (1 - 0.010) = 1.98 m.
  const Eigen::VectorXd at_truth = Residuals(*cost, {{0.0, 0.0, 0.0}, {1.98, 0.0, 0.0}, {0.012}});
  EXPECT_NEAR(at_truth.norm(), 0.0, 1e-12);
  // Where the dead reckoning's own estimate was right, no correction.
  const Eigen::VectorXd as_measured = Residuals(*cost, {{0.0, 0.0, 0.0}, {2.0, 0.0, 0.0}, {0.002}});
  EXPECT_NEAR(as_measured.norm(), 0.0, 1e-12);
  // A scale that is wrong by 0.01 leaves 2 cm along the way.
  const Eigen::VectorXd wrong = Residuals(*cost, {{0.0, 0.0, 0.0}, {2.0, 0.0, 0.0}, {0.012}});
  EXPECT_NEAR(wrong(0), 0.02, 1e-12);
  EXPECT_NEAR(wrong(1), 0.0, 1e-12);
}

TEST(OdometryFactorTest, RejectsACovarianceThatIsNotPositiveDefinite) {
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  covariance(2, 2) = 0.0;
  EXPECT_THROW(OdometryFactor(SE2(), covariance, 0.0), std::invalid_argument);
  covariance(2, 2) = -1.0;
  EXPECT_THROW(OdometryFactor(SE2(), covariance, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace parkslam::mapping
