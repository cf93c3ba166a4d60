#include "parkslam/eval/trajectory_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "parkslam/common/angles.h"

namespace parkslam::eval {
namespace {

constexpr TimeNs kStepNs = kNanosecondsPerSecond / 10;  // 10 Hz

// A straight drive along x at 1 m per pose (exact sums of path length).
Trajectory StraightLine(int poses, double scale = 1.0, TimeNs start_ns = 0) {
  Trajectory trajectory;
  for (int i = 0; i < poses; ++i) {
    trajectory.push_back({start_ns + i * kStepNs, SE2(scale * i, 0.0, 0.0)});
  }
  return trajectory;
}

// A smooth figure-eight-like lap, 10 Hz, yaw along the tangent.
Trajectory CurvedPath(int poses) {
  Trajectory trajectory;
  for (int i = 0; i < poses; ++i) {
    const double s = 0.01 * i;
    const double x = 30.0 * std::sin(s);
    const double y = 15.0 * std::sin(2.0 * s);
    const double yaw = std::atan2(30.0 * std::cos(2.0 * s), 30.0 * std::cos(s));
    trajectory.push_back({i * kStepNs, SE2(x, y, yaw)});
  }
  return trajectory;
}

TEST(EvaluateTrajectoryTest, IdenticalTrajectoriesHaveZeroErrors) {
  const Trajectory truth = CurvedPath(1200);
  const TrajectoryMetrics m = EvaluateTrajectory(truth, truth);
  EXPECT_EQ(m.matched_poses, 1200);
  EXPECT_NEAR(m.length_m, PathLength(truth), 1e-9);
  EXPECT_NEAR(m.ate_rmse_m, 0.0, 1e-9);
  EXPECT_NEAR(m.ate_max_m, 0.0, 1e-9);
  EXPECT_NEAR(m.yaw_rmse_rad, 0.0, 1e-12);
  EXPECT_NEAR(m.rpe_trans_rmse_m, 0.0, 1e-9);
  EXPECT_NEAR(m.rpe_yaw_rmse_rad, 0.0, 1e-12);
  EXPECT_NEAR(m.drift_per_100m_m, 0.0, 1e-9);
  EXPECT_NEAR(m.drift_percent, 0.0, 1e-9);
  EXPECT_NEAR(m.T_truth_estimate.translation().norm(), 0.0, 1e-9);
  EXPECT_NEAR(m.T_truth_estimate.yaw(), 0.0, 1e-12);
}

TEST(EvaluateTrajectoryTest, AlignmentRemovesRigidOffset) {
  const Trajectory truth = CurvedPath(1200);
  const SE2 T_estimate_truth(5.0, -3.0, 0.4);
  const TrajectoryMetrics m = EvaluateTrajectory(truth, Transformed(T_estimate_truth, truth));
  EXPECT_NEAR(m.ate_rmse_m, 0.0, 1e-6);
  EXPECT_NEAR(m.yaw_max_rad, 0.0, 1e-9);
  const SE2 expected = T_estimate_truth.inverse();
  EXPECT_NEAR(m.T_truth_estimate.x(), expected.x(), 1e-6);
  EXPECT_NEAR(m.T_truth_estimate.y(), expected.y(), 1e-6);
  EXPECT_NEAR(AngleDiff(m.T_truth_estimate.yaw(), expected.yaw()), 0.0, 1e-9);
}

TEST(EvaluateTrajectoryTest, WithoutAlignmentAteIsTheOffset) {
  const Trajectory truth = CurvedPath(1200);
  const TrajectoryMetricsOptions options{.align = false};
  const TrajectoryMetrics m =
      EvaluateTrajectory(truth, Transformed(SE2(3.0, 4.0, 0.0), truth), options);
  EXPECT_NEAR(m.ate_rmse_m, 5.0, 1e-9);
  EXPECT_NEAR(m.ate_mean_m, 5.0, 1e-9);
  EXPECT_NEAR(m.ate_max_m, 5.0, 1e-9);
  EXPECT_NEAR(m.yaw_max_rad, 0.0, 1e-12);
  EXPECT_EQ(m.T_truth_estimate.translation(), Eigen::Vector2d::Zero());
}

TEST(EvaluateTrajectoryTest, WithoutAlignmentYawOffsetShowsInYawError) {
  const Trajectory truth = CurvedPath(600);
  const TrajectoryMetricsOptions options{.align = false};
  const TrajectoryMetrics m =
      EvaluateTrajectory(truth, Transformed(SE2(0.0, 0.0, 0.1), truth), options);
  EXPECT_NEAR(m.yaw_rmse_rad, 0.1, 1e-12);
  EXPECT_NEAR(m.yaw_max_rad, 0.1, 1e-12);
}

TEST(EvaluateTrajectoryTest, RelativeErrorsIgnoreRigidOffset) {
  const Trajectory truth = CurvedPath(1200);
  const TrajectoryMetricsOptions options{.align = false};
  const TrajectoryMetrics m =
      EvaluateTrajectory(truth, Transformed(SE2(5.0, -3.0, 0.4), truth), options);
  EXPECT_GT(m.ate_rmse_m, 1.0);
  EXPECT_NEAR(m.rpe_trans_rmse_m, 0.0, 1e-9);
  EXPECT_NEAR(m.rpe_yaw_rmse_rad, 0.0, 1e-12);
  EXPECT_NEAR(m.drift_per_100m_m, 0.0, 1e-9);
}

TEST(EvaluateTrajectoryTest, OnePercentScaleGivesOneMetrePer100m) {
  // The estimate travels 1.01 m for every metre of truth.
  const TrajectoryMetrics m = EvaluateTrajectory(StraightLine(1001), StraightLine(1001, 1.01));
  EXPECT_NEAR(m.length_m, 1000.0, 1e-9);
  EXPECT_NEAR(m.drift_per_100m_m, 1.0, 1e-9);
  EXPECT_NEAR(m.drift_percent, 1.0, 1e-9);
  EXPECT_NEAR(m.rpe_trans_rmse_m, 0.1, 1e-9);
  EXPECT_NEAR(m.rpe_yaw_rmse_rad, 0.0, 1e-12);
}

TEST(EvaluateTrajectoryTest, DriftPercentUsesTheDriftSegment) {
  const TrajectoryMetricsOptions options{.drift_segment_m = 50.0};
  const TrajectoryMetrics m =
      EvaluateTrajectory(StraightLine(1001), StraightLine(1001, 1.01), options);
  EXPECT_NEAR(m.drift_per_100m_m, 0.5, 1e-9);
  EXPECT_NEAR(m.drift_percent, 1.0, 1e-9);
}

TEST(EvaluateTrajectoryTest, RpeSegmentEndsAtFirstPoseAtLeastSegmentAway) {
  const Trajectory truth = StraightLine(101);
  const Trajectory estimate = StraightLine(101, 1.01);
  // Poses 1 m apart: a 10 m segment ends exactly 10 poses on (0.10 m error),
  // a 10.001 m segment 11 poses on (0.11 m error).
  EXPECT_NEAR(EvaluateTrajectory(truth, estimate, {.rpe_segment_m = 10.0}).rpe_trans_rmse_m, 0.10,
              1e-9);
  EXPECT_NEAR(EvaluateTrajectory(truth, estimate, {.rpe_segment_m = 10.001}).rpe_trans_rmse_m, 0.11,
              1e-9);
}

TEST(EvaluateTrajectoryTest, DriftIsNaNWhenPathIsShorterThanSegment) {
  const TrajectoryMetrics m = EvaluateTrajectory(StraightLine(100), StraightLine(100, 1.01));
  EXPECT_NEAR(m.length_m, 99.0, 1e-9);
  EXPECT_TRUE(std::isnan(m.drift_per_100m_m));
  EXPECT_TRUE(std::isnan(m.drift_percent));
  EXPECT_NEAR(m.rpe_trans_rmse_m, 0.1, 1e-9);
}

TEST(EvaluateTrajectoryTest, RpeIsNaNWhenPathIsShorterThanSegment) {
  const TrajectoryMetrics m = EvaluateTrajectory(StraightLine(10), StraightLine(10, 1.01));
  EXPECT_TRUE(std::isnan(m.rpe_trans_rmse_m));
  EXPECT_TRUE(std::isnan(m.rpe_yaw_rmse_rad));
}

TEST(EvaluateTrajectoryTest, DropsEstimatePosesOutsideTruthSpan) {
  // Truth covers 10 s to 20 s; the estimate 0 s to 30 s, exact inside the
  // truth's span and far off outside it.
  const Trajectory truth = StraightLine(101, 1.0, 10 * kNanosecondsPerSecond);
  Trajectory estimate;
  for (int i = 0; i <= 300; ++i) {
    const TimeNs t_ns = i * kStepNs;
    const std::optional<SE2> T = PoseAt(truth, t_ns);
    estimate.push_back({t_ns, T ? *T : SE2(1000.0, 1000.0, 2.0)});
  }
  const TrajectoryMetrics m = EvaluateTrajectory(truth, estimate);
  EXPECT_EQ(m.matched_poses, 101);
  EXPECT_NEAR(m.length_m, 100.0, 1e-9);
  EXPECT_NEAR(m.ate_max_m, 0.0, 1e-9);
}

TEST(EvaluateTrajectoryTest, PairsEstimateWithInterpolatedTruth) {
  // Estimate stamped half-way between truth samples on a constant-speed line.
  const Trajectory truth = StraightLine(101);
  Trajectory estimate;
  for (int i = 0; i < 100; ++i) {
    estimate.push_back({i * kStepNs + kStepNs / 2, SE2(i + 0.5, 0.0, 0.0)});
  }
  const TrajectoryMetrics m = EvaluateTrajectory(truth, estimate, {.align = false});
  EXPECT_EQ(m.matched_poses, 100);
  EXPECT_NEAR(m.length_m, 99.0, 1e-9);
  EXPECT_NEAR(m.ate_max_m, 0.0, 1e-9);
}

TEST(EvaluateTrajectoryTest, UnsortedEstimateGivesSameResult) {
  const Trajectory truth = StraightLine(201);
  const Trajectory estimate = StraightLine(201, 1.01);
  Trajectory reversed(estimate.rbegin(), estimate.rend());
  const TrajectoryMetrics sorted_m = EvaluateTrajectory(truth, estimate);
  const TrajectoryMetrics reversed_m = EvaluateTrajectory(truth, reversed);
  EXPECT_DOUBLE_EQ(sorted_m.rpe_trans_rmse_m, reversed_m.rpe_trans_rmse_m);
  EXPECT_DOUBLE_EQ(sorted_m.drift_per_100m_m, reversed_m.drift_per_100m_m);
}

TEST(EvaluateTrajectoryTest, ThrowsWhenFewerThanTwoTimestampsOverlap) {
  const Trajectory truth = StraightLine(11, 1.0, 10 * kNanosecondsPerSecond);
  const Trajectory estimate{{5 * kNanosecondsPerSecond, SE2()},
                            {10 * kNanosecondsPerSecond, SE2()},
                            {25 * kNanosecondsPerSecond, SE2()}};
  try {
    EvaluateTrajectory(truth, estimate);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("overlap in fewer than 2 timestamps"), std::string::npos);
  }
}

TEST(EvaluateTrajectoryTest, AcceptsExactlyTwoOverlappingTimestamps) {
  const Trajectory truth = StraightLine(11);
  const Trajectory estimate{{0, SE2(0.0, 0.0, 0.0)}, {10 * kStepNs, SE2(10.0, 0.0, 0.0)}};
  EXPECT_EQ(EvaluateTrajectory(truth, estimate).matched_poses, 2);
}

TEST(EvaluateTrajectoryTest, ThrowsOnEmptyTruth) {
  EXPECT_THROW(EvaluateTrajectory({}, StraightLine(10)), std::invalid_argument);
}

TEST(EvaluateTrajectoryTest, ThrowsOnUnsortedTruth) {
  Trajectory truth = StraightLine(10);
  std::swap(truth[3], truth[4]);
  EXPECT_THROW(EvaluateTrajectory(truth, StraightLine(10)), std::invalid_argument);
}

TEST(EvaluateTrajectoryTest, ThrowsOnNonPositiveSegment) {
  EXPECT_THROW(EvaluateTrajectory(StraightLine(10), StraightLine(10), {.rpe_segment_m = 0.0}),
               std::invalid_argument);
}

TEST(EvaluateTrajectoryTest, HandlesOneHundredThousandPoses) {
  const TrajectoryMetrics m = EvaluateTrajectory(StraightLine(100001), StraightLine(100001, 1.01));
  EXPECT_EQ(m.matched_poses, 100001);
  EXPECT_NEAR(m.drift_per_100m_m, 1.0, 1e-6);
}

}  // namespace
}  // namespace parkslam::eval
