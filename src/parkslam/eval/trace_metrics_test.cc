#include "parkslam/eval/trace_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <stdexcept>
#include <vector>

#include "parkslam/common/angles.h"

namespace parkslam::eval {
namespace {

constexpr TimeNs kTraceStepNs = kNanosecondsPerSecond / 10;

// Samples a parametric path at `samples` + 1 points, u in [0, 1], yaw along
// the path.
Trajectory Sampled(const std::function<Eigen::Vector2d(double)>& path, int samples) {
  Trajectory trajectory;
  for (int i = 0; i <= samples; ++i) {
    const double u = static_cast<double>(i) / samples;
    const Eigen::Vector2d p = path(u);
    const Eigen::Vector2d ahead = path(std::min(1.0, u + 1e-4)) - path(std::max(0.0, u - 1e-4));
    trajectory.push_back({i * kTraceStepNs, SE2(p, std::atan2(ahead.y(), ahead.x()))});
  }
  return trajectory;
}

// Counter-clockwise circle about the origin from angle 0 over `turns`.
Trajectory Circle(double radius_m, double turns) {
  const int samples = static_cast<int>(std::ceil(2.0 * kPi * 10.0 * turns / 0.1));
  return Sampled(
      [=](double u) {
        const double a = 2.0 * kPi * turns * u;
        return Eigen::Vector2d(radius_m * std::cos(a), radius_m * std::sin(a));
      },
      samples);
}

Trajectory StraightX(double from_m, double to_m, double y_m) {
  return Sampled([=](double u) { return Eigen::Vector2d(from_m + u * (to_m - from_m), y_m); },
                 static_cast<int>(std::ceil((to_m - from_m) / 0.2)));
}

// A gently winding human-like drive.
Trajectory Winding() {
  return Sampled(
      [](double u) {
        return Eigen::Vector2d(60.0 * u, 3.0 * std::sin(2.0 * kPi * u) + std::sin(7.0 * u));
      },
      400);
}

TEST(EvaluateTraceFollowingTest, IdenticalRunsHaveZeroRepeatStd) {
  const Trajectory trace = Winding();
  const TraceFollowingMetrics m = EvaluateTraceFollowing(trace, {trace, trace, trace});
  EXPECT_EQ(m.runs, 3);
  EXPECT_EQ(m.stations, static_cast<int>(std::floor(PathLength(trace) / 0.5)) + 1);
  EXPECT_EQ(m.repeat_stations, m.stations);
  EXPECT_NEAR(m.repeat_std_m, 0.0, 1e-12);
  EXPECT_NEAR(m.repeat_std_max_m, 0.0, 1e-12);
  EXPECT_NEAR(m.lateral_mean_all_m, 0.0, 1e-9);
  EXPECT_NEAR(m.lateral_max_all_m, 0.0, 1e-9);
}

TEST(EvaluateTraceFollowingTest, SymmetricOffsetsGiveTheirSpread) {
  // Three quarters of a circle of radius 10 m; the runs 0.1 m inside (left)
  // and 0.1 m outside (right).
  const Trajectory trace = Circle(10.0, 0.75);
  const TraceFollowingMetrics m =
      EvaluateTraceFollowing(trace, {Circle(9.9, 0.75), Circle(10.1, 0.75)});
  EXPECT_NEAR(m.repeat_std_m, 0.1, 1e-3);
  EXPECT_NEAR(m.repeat_std_max_m, 0.1, 1e-3);
  EXPECT_NEAR(m.lateral_mean_all_m, 0.1, 1e-3);
  EXPECT_NEAR(m.lateral_max_all_m, 0.1, 1e-3);
  ASSERT_EQ(m.lateral_offset_m.size(), 2u);
  EXPECT_NEAR(m.lateral_offset_m[0][10], 0.1, 1e-3);  // inside is left
  EXPECT_NEAR(m.lateral_offset_m[1][10], -0.1, 1e-3);
}

TEST(EvaluateTraceFollowingTest, ConstantOffsetHasNoSpread) {
  const Trajectory trace = StraightX(0.0, 30.0, 0.0);
  const TraceFollowingMetrics m =
      EvaluateTraceFollowing(trace, {StraightX(0.0, 30.0, 0.3), StraightX(0.0, 30.0, 0.3)});
  EXPECT_NEAR(m.repeat_std_m, 0.0, 1e-12);
  EXPECT_NEAR(m.lateral_mean_all_m, 0.3, 1e-12);
}

TEST(EvaluateTraceFollowingTest, SecondPassOfLoopIsMatchedToSecondPass) {
  // The trace goes twice round a circle of radius 10 m; the run copies the
  // first pass and drives the second 0.2 m inside.
  const Trajectory trace = Circle(10.0, 2.0);
  const double lap_m = PathLength(trace) / 2.0;
  Trajectory run;
  for (const TimedPose& pose : trace) {
    const bool second_pass = pose.t_ns > trace.back().t_ns / 2;
    const double scale = second_pass ? 9.8 / 10.0 : 1.0;
    run.push_back(
        {pose.t_ns, SE2(scale * pose.T_map_vehicle.translation(), pose.T_map_vehicle.yaw())});
  }
  const TraceFollowingMetrics m = EvaluateTraceFollowing(trace, {run});
  EXPECT_NEAR(m.lateral_max_all_m, 0.2, 1e-3);
  ASSERT_EQ(m.station_s_m.size(), static_cast<size_t>(m.stations));
  int first = 0, second = 0;
  for (int k = 0; k < m.stations; ++k) {
    const double s = m.station_s_m[k];
    const double offset = m.lateral_offset_m[0][k];
    ASSERT_FALSE(std::isnan(offset)) << "s = " << s;
    if (s < lap_m - 0.5) {
      EXPECT_NEAR(offset, 0.0, 1e-9) << "s = " << s;
      ++first;
    } else if (s > lap_m + 0.5) {
      EXPECT_NEAR(offset, 0.2, 1e-3) << "s = " << s;
      ++second;
    }
  }
  EXPECT_GT(first, 100);
  EXPECT_GT(second, 100);
  // The skips select one pass.
  EXPECT_NEAR(EvaluateTraceFollowing(trace, {run}, 0.5, 0.0, lap_m + 0.5).lateral_max_all_m, 0.0,
              1e-9);
  EXPECT_NEAR(EvaluateTraceFollowing(trace, {run}, 0.5, lap_m + 0.5, 0.0).lateral_mean_all_m, 0.2,
              1e-3);
}

TEST(EvaluateTraceFollowingTest, MissingCoverageIsExcluded) {
  // Run 0 covers the whole 40 m at +0.1 m; run 1 stops after 20 m at -0.1 m.
  const Trajectory trace = StraightX(0.0, 40.0, 0.0);
  const TraceFollowingMetrics m =
      EvaluateTraceFollowing(trace, {StraightX(0.0, 40.0, 0.1), StraightX(0.0, 20.0, -0.1)});
  EXPECT_EQ(m.stations, 81);
  EXPECT_EQ(m.repeat_stations, 41);  // x = 0, 0.5, ..., 20
  EXPECT_NEAR(m.repeat_std_m, 0.1, 1e-12);
  EXPECT_NEAR(m.lateral_mean_m[1], 0.1, 1e-12);
  EXPECT_NEAR(m.lateral_max_m[1], 0.1, 1e-12);
  EXPECT_FALSE(std::isnan(m.lateral_offset_m[1][40]));  // x = 20
  EXPECT_TRUE(std::isnan(m.lateral_offset_m[1][41]));   // x = 20.5
  EXPECT_FALSE(std::isnan(m.lateral_offset_m[0][80]));
}

TEST(EvaluateTraceFollowingTest, RunsFartherThan5mDoNotCover) {
  const Trajectory trace = StraightX(0.0, 20.0, 0.0);
  const TraceFollowingMetrics near = EvaluateTraceFollowing(trace, {StraightX(0.0, 20.0, 4.9)});
  EXPECT_NEAR(near.lateral_mean_all_m, 4.9, 1e-12);
  const TraceFollowingMetrics far = EvaluateTraceFollowing(trace, {StraightX(0.0, 20.0, 5.1)});
  EXPECT_TRUE(std::isnan(far.lateral_mean_m[0]));
  EXPECT_TRUE(std::isnan(far.lateral_mean_all_m));
  // One run: no spread to measure.
  EXPECT_TRUE(std::isnan(near.repeat_std_m));
  EXPECT_EQ(near.repeat_stations, 0);
}

TEST(EvaluateTraceFollowingTest, SkipsAndSpacingSetTheStations) {
  const Trajectory trace = StraightX(0.0, 10.0, 0.0);
  const TraceFollowingMetrics m = EvaluateTraceFollowing(trace, {trace}, 1.0, 2.0, 3.0);
  ASSERT_EQ(m.stations, 6);
  EXPECT_NEAR(m.station_s_m.front(), 2.0, 1e-12);
  EXPECT_NEAR(m.station_s_m.back(), 7.0, 1e-12);
}

TEST(EvaluateTraceFollowingTest, RejectsInvalidInputs) {
  const Trajectory trace = StraightX(0.0, 10.0, 0.0);
  EXPECT_THROW(EvaluateTraceFollowing(trace, {}), std::invalid_argument);
  EXPECT_THROW(EvaluateTraceFollowing(StraightX(0.0, 0.9, 0.0), {trace}), std::invalid_argument);
  EXPECT_NO_THROW(EvaluateTraceFollowing(StraightX(0.0, 1.1, 0.0), {trace}));
  EXPECT_THROW(EvaluateTraceFollowing(trace, {trace}, 0.0), std::invalid_argument);
  EXPECT_THROW(EvaluateTraceFollowing(trace, {trace}, 0.5, 6.0, 5.0), std::invalid_argument);
}

}  // namespace
}  // namespace parkslam::eval
