#include "parkslam/mapping/costs/max_mixture_corner_factor.h"

#include <ceres/problem.h>
#include <ceres/solver.h>
#include <gtest/gtest.h>

#include <Eigen/Core>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include "parkslam/common/angles.h"
#include "parkslam/common/random.h"
#include "parkslam/common/se2.h"
#include "parkslam/mapping/costs/angle.h"
#include "parkslam/mapping/costs/cost_test_util.h"
#include "parkslam/mapping/costs/prior_factor.h"

namespace parkslam::mapping {
namespace {

using testing::Blocks;
using testing::Jacobians;
using testing::JacobiansMatchNumeric;
using testing::Pointers;
using testing::Residuals;

constexpr double kSigmaM = 0.1;

CornerMeasurement Measurement(double x, double y, double sigma = kSigmaM) {
  return {Eigen::Vector2d(x, y), sigma * sigma * Eigen::Matrix2d::Identity()};
}

// The map point that a pose sees at p_vehicle.
std::vector<double> MapPoint(const std::vector<double>& pose, const Eigen::Vector2d& p_vehicle) {
  const Eigen::Vector2d p = SE2(pose[0], pose[1], pose[2]) * p_vehicle;
  return {p.x(), p.y()};
}

// pose, then the corners in candidate-major order.
Blocks MakeBlocks(const std::vector<double>& pose, const Blocks& corners) {
  Blocks blocks = {pose};
  blocks.insert(blocks.end(), corners.begin(), corners.end());
  return blocks;
}

int Chosen(const MaxMixtureCornerFactor& factor, const Blocks& blocks) {
  return factor.ChosenComponent(Pointers(blocks).data());
}

// Pose at the origin facing +y: a corner at vehicle (x, y) is at map (-y, x).
const std::vector<double> kPoseFacingPlusY = {0.0, 0.0, kPi / 2};

TEST(MaxMixtureCornerFactorTest, LayoutFollowsMeasurementsAndCandidates) {
  const MaxMixtureCornerFactor factor({Measurement(1, 0), Measurement(2, 0), Measurement(3, 0)},
                                      {0.5, 0.3}, 0.1, 9.0);
  EXPECT_EQ(factor.num_residuals(), 2 * 3 + 1);
  EXPECT_EQ(factor.parameter_block_sizes(), (std::vector<int>{3, 2, 2, 2, 2, 2, 2}));
  EXPECT_EQ(factor.CornerBlockIndex(0, 0), 1);
  EXPECT_EQ(factor.CornerBlockIndex(1, 2), 6);
}

TEST(MaxMixtureCornerFactorTest, ResidualOfChosenCandidateByHand) {
  // One corner measured 2 m ahead; candidate 0 is 2.1 m ahead (0.1 m = 1
  // sigma off along the vehicle x), candidate 1 is far away.
  const MaxMixtureCornerFactor factor({Measurement(2.0, 0.0)}, {0.5, 0.5}, 0.01, 25.0);
  const Blocks blocks = MakeBlocks(kPoseFacingPlusY, {{0.0, 2.1}, {5.0, 5.0}});
  EXPECT_EQ(Chosen(factor, blocks), 0);
  const Eigen::VectorXd r = Residuals(factor, blocks);
  ASSERT_EQ(r.size(), 3);
  EXPECT_NEAR(r(0), 1.0, 1e-12);
  EXPECT_NEAR(r(1), 0.0, 1e-12);
  EXPECT_NEAR(r(2), 0.0, 1e-12);  // equal weights: N_0 = N_min
}

// Two candidates, w0 = 0.6 and w1 = 0.3; candidate 0 sits 0.2 m (chi2 = 4)
// off. Candidate 1, d1 off sideways, wins iff
//   chi2_1 < chi2_0 + 2 log(w1 / w0) = 4 - 2 log 2,  d1* = 0.1 sqrt(4 - 2 log 2).
class TwoCandidateSwitchTest : public ::testing::Test {
 protected:
  const MaxMixtureCornerFactor factor_{{Measurement(4.0, 0.0)}, {0.6, 0.3}, 1e-3, 25.0};
  const double switch_d1_ = kSigmaM * std::sqrt(4.0 - 2.0 * std::log(2.0));

  Blocks At(double d1) const {
    return MakeBlocks(kPoseFacingPlusY, {MapPoint(kPoseFacingPlusY, {4.2, 0.0}),
                                         MapPoint(kPoseFacingPlusY, {4.0, d1})});
  }
};

TEST_F(TwoCandidateSwitchTest, LighterCandidateWinsJustBelowTheSwitch) {
  EXPECT_EQ(Chosen(factor_, At(switch_d1_ - 1e-6)), 1);
}

TEST_F(TwoCandidateSwitchTest, HeavierCandidateWinsJustAboveTheSwitch) {
  EXPECT_EQ(Chosen(factor_, At(switch_d1_ + 1e-6)), 0);
}

TEST_F(TwoCandidateSwitchTest, CostIsContinuousAcrossTheSwitch) {
  const double below = 0.5 * Residuals(factor_, At(switch_d1_ - 1e-9)).squaredNorm();
  const double above = 0.5 * Residuals(factor_, At(switch_d1_ + 1e-9)).squaredNorm();
  EXPECT_NEAR(below, above, 1e-6);
  // ... while the residual vector jumps from one candidate's error to the other's.
  const Eigen::VectorXd r_below = Residuals(factor_, At(switch_d1_ - 1e-9));
  const Eigen::VectorXd r_above = Residuals(factor_, At(switch_d1_ + 1e-9));
  EXPECT_NEAR(r_below(0), 0.0, 1e-9);  // candidate 1: error only sideways
  EXPECT_NEAR(r_above(0), 2.0, 1e-9);  // candidate 0: 0.2 m ahead = 2 sigma
}

// One candidate (w = 0.8) against the null (w_null = 0.05, null_chi2 = 9):
// the candidate wins iff chi2 < 9 + 2 log(16).
class CandidateVersusNullTest : public ::testing::Test {
 protected:
  const MaxMixtureCornerFactor factor_{
      {Measurement(3.0, 1.0), Measurement(3.0, -1.5)}, {0.8}, 0.05, 9.0};
  const double threshold_ = 9.0 + 2.0 * std::log(0.8 / 0.05);

  // Measurement 0 exact; measurement 1 off by d sideways: chi2 = (d / 0.1)^2.
  Blocks At(double chi2) const {
    const double d = kSigmaM * std::sqrt(chi2);
    return MakeBlocks(kPoseFacingPlusY, {MapPoint(kPoseFacingPlusY, {3.0, 1.0}),
                                         MapPoint(kPoseFacingPlusY, {3.0, -1.5 + d})});
  }
};

TEST_F(CandidateVersusNullTest, AcceptanceThresholdIsNullChi2PlusTwoLogWeightRatio) {
  EXPECT_NEAR(MaxMixtureCornerFactor::CandidateAcceptanceChi2(0.8, 0.05, 9.0), threshold_, 1e-12);
  EXPECT_NEAR(threshold_, 14.545177444479562, 1e-12);
}

TEST_F(CandidateVersusNullTest, CandidateWinsJustBelowTheThreshold) {
  const Blocks blocks = At(threshold_ - 1e-4);
  EXPECT_NEAR(factor_.CandidateChi2(Pointers(blocks).data(), 0), threshold_ - 1e-4, 1e-8);
  EXPECT_EQ(Chosen(factor_, blocks), 0);
  EXPECT_GT(Residuals(factor_, blocks).head(4).norm(), 3.0);
}

TEST_F(CandidateVersusNullTest, NullWinsJustAboveTheThreshold) {
  const Blocks blocks = At(threshold_ + 1e-4);
  EXPECT_EQ(Chosen(factor_, blocks), MaxMixtureCornerFactor::kNullComponent);
  EXPECT_EQ(Residuals(factor_, blocks).head(4).norm(), 0.0);
}

TEST_F(CandidateVersusNullTest, NullComponentGivesZeroJacobians) {
  const Blocks blocks = At(threshold_ + 5.0);
  ASSERT_EQ(Chosen(factor_, blocks), MaxMixtureCornerFactor::kNullComponent);
  Eigen::VectorXd r;
  const auto jacobians = Jacobians(factor_, blocks, &r);
  for (const auto& j : jacobians) EXPECT_EQ(j.cwiseAbs().maxCoeff(), 0.0);
  // N_null = -log 0.05 + 4.5 against N_min = -log 0.8.
  const double n_null = -std::log(0.05) + 4.5;
  EXPECT_NEAR(r(4), std::sqrt(2.0 * (n_null + std::log(0.8))), 1e-12);
}

TEST(MaxMixtureCornerFactorTest, NormalizationEntryIsNonNegativeAndGivesCostAboveMin) {
  Random random(23);
  int chosen_null = 0, chosen_candidate = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const int num_j = 1 + static_cast<int>(random.Index(4));
    const int num_k = 1 + static_cast<int>(random.Index(3));
    std::vector<CornerMeasurement> measurements;
    for (int j = 0; j < num_j; ++j) {
      measurements.push_back(
          Measurement(random.Uniform(1, 8), random.Uniform(-4, 4), random.Uniform(0.05, 0.3)));
    }
    std::vector<double> weights;
    for (int k = 0; k < num_k; ++k) weights.push_back(random.Uniform(0.01, 1.0));
    const double null_weight = random.Bernoulli(0.3) ? 0.0 : random.Uniform(0.001, 0.5);
    const MaxMixtureCornerFactor factor(measurements, weights, null_weight,
                                        random.Uniform(1.0, 30.0));
    const std::vector<double> pose = {random.Uniform(-5, 5), random.Uniform(-5, 5),
                                      random.Uniform(-kPi, kPi)};
    Blocks corners;
    for (int k = 0; k < num_k; ++k) {
      const double spread = random.Uniform(0.0, 1.0);
      for (int j = 0; j < num_j; ++j) {
        const Eigen::Vector2d noisy =
            measurements[static_cast<std::size_t>(j)].z_vehicle +
            Eigen::Vector2d(random.Gaussian(spread), random.Gaussian(spread));
        corners.push_back(MapPoint(pose, noisy));
      }
    }
    const Blocks blocks = MakeBlocks(pose, corners);
    const Eigen::VectorXd r = Residuals(factor, blocks);
    const int chosen = Chosen(factor, blocks);
    (chosen == MaxMixtureCornerFactor::kNullComponent ? chosen_null : chosen_candidate)++;
    const double cost_chosen = factor.ComponentCost(Pointers(blocks).data(), chosen);
    EXPECT_GE(r(r.size() - 1), 0.0);
    EXPECT_NEAR(0.5 * r.squaredNorm(), cost_chosen - factor.MinNormalization(),
                1e-9 * (1.0 + cost_chosen));
    for (int k = -1; k < num_k; ++k) {
      EXPECT_LE(cost_chosen, factor.ComponentCost(Pointers(blocks).data(), k));
    }
  }
  // Both kinds of component were exercised.
  EXPECT_GT(chosen_null, 10);
  EXPECT_GT(chosen_candidate, 10);
}

TEST(MaxMixtureCornerFactorTest, JacobiansMatchNumericAwayFromTheSwitch) {
  Random random(29);
  const std::vector<CornerMeasurement> measurements = {
      {Eigen::Vector2d(3.0, 1.2), (Eigen::Matrix2d() << 0.04, 0.01, 0.01, 0.02).finished()},
      {Eigen::Vector2d(5.5, -1.3), (Eigen::Matrix2d() << 0.02, -0.005, -0.005, 0.06).finished()}};
  const MaxMixtureCornerFactor factor(measurements, {0.3, 0.5, 0.2}, 0.01, 30.0);
  for (const double yaw : {kPi - 1e-4, -kPi + 1e-4, kPi, 0.5, -2.2}) {
    for (int trial = 0; trial < 3; ++trial) {
      const std::vector<double> pose = {random.Uniform(-20, 20), random.Uniform(-20, 20), yaw};
      Blocks corners;
      for (int k = 0; k < 3; ++k) {
        // Candidate 1 close (about 1 sigma), candidates 0 and 2 at least 2 m off.
        const double spread = k == 1 ? 0.1 : 1.0;
        for (const auto& m : measurements) {
          corners.push_back(
              MapPoint(pose, m.z_vehicle +
                                 Eigen::Vector2d(random.Uniform(-spread, spread),
                                                 random.Uniform(-spread, spread)) +
                                 (k == 1 ? Eigen::Vector2d(0.0, 0.0) : Eigen::Vector2d(3.0, 0.0))));
        }
      }
      const Blocks blocks = MakeBlocks(pose, corners);
      ASSERT_EQ(Chosen(factor, blocks), 1);
      EXPECT_TRUE(JacobiansMatchNumeric(factor, blocks)) << yaw;
      const auto jacobians = Jacobians(factor, blocks);
      for (int j = 0; j < 2; ++j) {
        EXPECT_EQ(jacobians[static_cast<std::size_t>(factor.CornerBlockIndex(0, j))]
                      .cwiseAbs()
                      .maxCoeff(),
                  0.0);
        EXPECT_EQ(jacobians[static_cast<std::size_t>(factor.CornerBlockIndex(2, j))]
                      .cwiseAbs()
                      .maxCoeff(),
                  0.0);
        EXPECT_GT(jacobians[static_cast<std::size_t>(factor.CornerBlockIndex(1, j))]
                      .cwiseAbs()
                      .maxCoeff(),
                  1.0);
      }
      for (const auto& jac : jacobians) {
        EXPECT_EQ(jac.row(jac.rows() - 1).cwiseAbs().maxCoeff(), 0.0);
      }
    }
  }
}

TEST(MaxMixtureCornerFactorTest, EvaluateSkipsNullJacobianBlocks) {
  const MaxMixtureCornerFactor factor({Measurement(2.0, 0.5)}, {0.5, 0.5}, 0.0, 0.0);
  const Blocks blocks =
      MakeBlocks({1.0, 2.0, 0.3}, {MapPoint({1.0, 2.0, 0.3}, {2.1, 0.4}), {9.0, 9.0}});
  const auto full = Jacobians(factor, blocks);
  // The pose held constant: Ceres passes no Jacobian for it.
  Eigen::Matrix<double, 3, 2, Eigen::RowMajor> corner0, corner1;
  double* jacobians[] = {nullptr, corner0.data(), corner1.data()};
  Eigen::Vector3d r;
  ASSERT_TRUE(factor.Evaluate(Pointers(blocks).data(), r.data(), jacobians));
  EXPECT_TRUE(corner0.isApprox(full[1]));
  EXPECT_EQ(corner1.cwiseAbs().maxCoeff(), 0.0);
}

TEST(MaxMixtureCornerFactorTest, WithoutNullTheBestCandidateIsAlwaysChosen) {
  const MaxMixtureCornerFactor factor({Measurement(2.0, 0.0)}, {0.5, 0.5}, 0.0, 9.0);
  EXPECT_FALSE(factor.has_null());
  // Both candidates 50 sigma off or more: the nearer one is still chosen.
  const Blocks blocks = MakeBlocks(kPoseFacingPlusY, {{0.0, 9.0}, {0.0, 7.0}});
  EXPECT_EQ(Chosen(factor, blocks), 1);
  EXPECT_DOUBLE_EQ(factor.MinNormalization(), -std::log(0.5));
}

TEST(MaxMixtureCornerFactorTest, CeresPicksTheNearCandidateAndLeavesTheFarOneAlone) {
  const SE2 T_map_vehicle(10.0, 5.0, kPi - 0.01);
  std::vector<double> pose = {T_map_vehicle.x(), T_map_vehicle.y(), T_map_vehicle.yaw()};
  const Eigen::Vector2d z(3.0, -1.0);
  const Eigen::Vector2d truth = T_map_vehicle * z;
  // Candidate 0 far (3 m off), candidate 1 near (0.3 m off).
  std::vector<double> far = {truth.x() + 3.0, truth.y()};
  std::vector<double> near = {truth.x() - 0.2, truth.y() + 0.2236};
  const std::vector<double> far_before = far;

  ceres::Problem problem;
  problem.AddParameterBlock(pose.data(), 3, new Pose2Manifold);
  problem.AddResidualBlock(
      PosePriorFactor::Create(T_map_vehicle, Eigen::Vector3d(1e-4, 1e-4, 1e-6).asDiagonal()),
      nullptr, pose.data());
  MaxMixtureCornerFactor* factor =
      MaxMixtureCornerFactor::Create({Measurement(z.x(), z.y())}, {0.5, 0.5}, 0.01, 25.0);
  std::vector<double*> blocks = {pose.data(), far.data(), near.data()};
  problem.AddResidualBlock(factor, nullptr, blocks);
  ASSERT_EQ(factor->ChosenComponent(blocks.data()), 1);

  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();

  EXPECT_EQ(factor->ChosenComponent(blocks.data()), 1);
  EXPECT_NEAR(near[0], truth.x(), 1e-6);
  EXPECT_NEAR(near[1], truth.y(), 1e-6);
  EXPECT_EQ(far, far_before);
  EXPECT_NEAR(summary.final_cost, 0.0, 1e-10);
  EXPECT_GT(pose[2], 0.0);  // stayed on the +pi side, wrapped by the manifold
}

TEST(MaxMixtureCornerFactorTest, RejectsInvalidInput) {
  EXPECT_THROW(MaxMixtureCornerFactor({}, {1.0}, 0.1, 9.0), std::invalid_argument);
  EXPECT_THROW(MaxMixtureCornerFactor({Measurement(1, 0)}, {}, 0.1, 9.0), std::invalid_argument);
  EXPECT_THROW(MaxMixtureCornerFactor({Measurement(1, 0)}, {0.0}, 0.1, 9.0), std::invalid_argument);
  EXPECT_THROW(MaxMixtureCornerFactor({Measurement(1, 0)}, {0.5}, -0.1, 9.0),
               std::invalid_argument);
  EXPECT_THROW(MaxMixtureCornerFactor({Measurement(1, 0)}, {0.5}, 0.1, -1.0),
               std::invalid_argument);
}

}  // namespace
}  // namespace parkslam::mapping
