#include "parkslam/graph/max_mixture_pose_edge_factor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <stdexcept>

#include "parkslam/graph/pose_edge_factor.h"
#include "parkslam/graph/pose_graph.h"

namespace parkslam::graph {
namespace {

Eigen::Matrix3d TestInformation() {
  Eigen::Matrix3d information;
  information << 400.0, 20.0, 5.0,  //
      20.0, 300.0, -4.0,            //
      5.0, -4.0, 2500.0;
  return information;
}

// Residuals and Jacobians of a two-block cost function.
struct Evaluation {
  Eigen::VectorXd r;
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> J_a, J_b;
};

Evaluation Evaluate(const ceres::CostFunction& f, const double* a, const double* b) {
  Evaluation out;
  const int n = f.num_residuals();
  out.r.resize(n);
  out.J_a.resize(n, 3);
  out.J_b.resize(n, 3);
  const double* parameters[2] = {a, b};
  double* jacobians[2] = {out.J_a.data(), out.J_b.data()};
  EXPECT_TRUE(f.Evaluate(parameters, out.r.data(), jacobians));
  return out;
}

TEST(MaxMixturePoseEdgeFactorTest, ThresholdIsWhereTheTwoCostsMeet) {
  // 2 (-log 0.01 - 1.5 log 1e-6) / (1 - 1e-6)
  EXPECT_NEAR(MaxMixturePoseEdgeFactor::NullThresholdChi2(0.01, 1e-6), 50.6568, 1e-3);
  // A heavier null switches sooner.
  EXPECT_LT(MaxMixturePoseEdgeFactor::NullThresholdChi2(0.5, 1e-6),
            MaxMixturePoseEdgeFactor::NullThresholdChi2(0.01, 1e-6));
}

TEST(MaxMixturePoseEdgeFactorTest, SmallErrorIsThePlainEdge) {
  const SE2 Z(2.0, 0.5, 0.3);
  const Eigen::Matrix3d information = TestInformation();
  const MaxMixturePoseEdgeFactor mixture(Z, information, 0.01, 1e-6);
  std::unique_ptr<ceres::CostFunction> plain(PoseEdgeFactor::Create(Z, information));
  const double a[3] = {1.0, -2.0, 0.4};
  const SE2 B = SE2(a[0], a[1], a[2]) * Z * SE2(0.03, -0.02, 0.01);
  const double b[3] = {B.x(), B.y(), B.yaw()};
  const Evaluation m = Evaluate(mixture, a, b);
  const Evaluation p = Evaluate(*plain, a, b);
  EXPECT_FALSE(mixture.NullChosen(a, b));
  EXPECT_LT((m.r.head<3>() - p.r).norm(), 1e-12);
  EXPECT_EQ(m.r(3), 0.0);
  EXPECT_LT((m.J_a.topRows(3) - p.J_a).norm(), 1e-9);
  EXPECT_LT((m.J_b.topRows(3) - p.J_b).norm(), 1e-9);
  EXPECT_EQ(m.J_a.row(3).norm(), 0.0);
  // The plain residual's norm is the graph's chi2 of the edge.
  PoseGraph graph;
  graph.poses[0] = SE2(a[0], a[1], a[2]);
  graph.poses[1] = B;
  const PoseEdge edge{0, 1, Z, information};
  EXPECT_NEAR(p.r.squaredNorm(), PoseEdgeChi2(graph, edge), 1e-9);
}

TEST(MaxMixturePoseEdgeFactorTest, LargeErrorIsTheWideNullWithItsNormalization) {
  const SE2 Z(2.0, 0.5, 0.3);
  const Eigen::Matrix3d information = TestInformation();
  const double w = 0.01, s = 1e-6;
  const MaxMixturePoseEdgeFactor mixture(Z, information, w, s);
  std::unique_ptr<ceres::CostFunction> plain(PoseEdgeFactor::Create(Z, information));
  const double a[3] = {0.0, 0.0, 0.0};
  const double b[3] = {5.0, 4.0, -1.0};  // far from Z
  const Evaluation m = Evaluate(mixture, a, b);
  const Evaluation p = Evaluate(*plain, a, b);
  ASSERT_TRUE(mixture.NullChosen(a, b));
  EXPECT_LT((m.r.head<3>() - std::sqrt(s) * p.r).norm(), 1e-9);
  // 0.5 ||r||^2 = cost_0 - N_1 = -log w - 1.5 log s + 0.5 s chi2.
  const double chi2 = p.r.squaredNorm();
  EXPECT_NEAR(0.5 * m.r.squaredNorm(), -std::log(w) - 1.5 * std::log(s) + 0.5 * s * chi2, 1e-9);
  EXPECT_LT((m.J_b.topRows(3) - std::sqrt(s) * p.J_b).norm(), 1e-9);
  EXPECT_EQ(m.J_b.row(3).norm(), 0.0);
}

TEST(MaxMixturePoseEdgeFactorTest, SwitchesExactlyAtTheThreshold) {
  const SE2 Z(1.0, 0.0, 0.0);
  const Eigen::Matrix3d information = Eigen::Matrix3d::Identity() * 100.0;
  const MaxMixturePoseEdgeFactor mixture(Z, information, 0.01, 1e-6);
  const double threshold = MaxMixturePoseEdgeFactor::NullThresholdChi2(0.01, 1e-6);
  // An error along x only: chi2 = 100 dx^2.
  const double dx_at = std::sqrt(threshold / 100.0);
  const double a[3] = {0.0, 0.0, 0.0};
  const double below[3] = {1.0 + 0.999 * dx_at, 0.0, 0.0};
  const double above[3] = {1.0 + 1.001 * dx_at, 0.0, 0.0};
  EXPECT_FALSE(mixture.NullChosen(a, below));
  EXPECT_TRUE(mixture.NullChosen(a, above));
}

TEST(MaxMixturePoseEdgeFactorTest, RejectsInvalidNull) {
  const Eigen::Matrix3d information = Eigen::Matrix3d::Identity();
  EXPECT_THROW(MaxMixturePoseEdgeFactor(SE2(), information, 0.0, 1e-6), std::invalid_argument);
  EXPECT_THROW(MaxMixturePoseEdgeFactor(SE2(), information, 1.5, 1e-6), std::invalid_argument);
  EXPECT_THROW(MaxMixturePoseEdgeFactor(SE2(), information, 0.1, 1.0), std::invalid_argument);
  EXPECT_THROW(MaxMixturePoseEdgeFactor(SE2(), information, 0.1, 0.0), std::invalid_argument);
}

TEST(PoseGraphTest, CheckNamesTheBadEdge) {
  PoseGraph graph;
  graph.poses[0] = SE2();
  graph.poses[1] = SE2(1.0, 0.0, 0.0);
  graph.pose_edges.push_back({0, 1, SE2(1.0, 0.0, 0.0), Eigen::Matrix3d::Identity()});
  EXPECT_NO_THROW(CheckPoseGraph(graph));
  graph.pose_edges.push_back({0, 7, SE2(), Eigen::Matrix3d::Identity()});
  try {
    CheckPoseGraph(graph);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "pose edge 1 (0 -> 7): names a pose vertex that does not exist");
  }
  graph.pose_edges[1] = {1, 0, SE2(), -Eigen::Matrix3d::Identity()};
  EXPECT_THROW(CheckPoseGraph(graph), std::invalid_argument);
}

TEST(PoseGraphTest, OnlyConsecutiveIdsAreOdometry) {
  EXPECT_TRUE(IsOdometry({3, 4, SE2(), Eigen::Matrix3d::Identity()}));
  EXPECT_TRUE(IsOdometry({4, 3, SE2(), Eigen::Matrix3d::Identity()}));
  EXPECT_FALSE(IsOdometry({3, 5, SE2(), Eigen::Matrix3d::Identity()}));
}

}  // namespace
}  // namespace parkslam::graph
