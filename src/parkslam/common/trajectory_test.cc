#include "parkslam/common/trajectory.h"

#include <gtest/gtest.h>

namespace parkslam {
namespace {

Trajectory Straight() {
  return {{0, SE2(0, 0, 0)},
          {kNanosecondsPerSecond, SE2(2, 0, 0.2)},
          {2 * kNanosecondsPerSecond, SE2(2, 3, 0.4)}};
}

TEST(TrajectoryTest, PoseAtInterpolatesBetweenStamps) {
  const auto pose = PoseAt(Straight(), kNanosecondsPerSecond / 4);
  ASSERT_TRUE(pose.has_value());
  EXPECT_NEAR(pose->x(), 0.5, 1e-12);
  EXPECT_NEAR(pose->yaw(), 0.05, 1e-12);
}

TEST(TrajectoryTest, PoseAtExactStampAndEnds) {
  EXPECT_NEAR(PoseAt(Straight(), 0)->x(), 0.0, 1e-12);
  EXPECT_NEAR(PoseAt(Straight(), 2 * kNanosecondsPerSecond)->y(), 3.0, 1e-12);
}

TEST(TrajectoryTest, PoseAtOutsideSpanIsEmpty) {
  EXPECT_FALSE(PoseAt(Straight(), -1).has_value());
  EXPECT_FALSE(PoseAt(Straight(), 2 * kNanosecondsPerSecond + 1).has_value());
  EXPECT_FALSE(PoseAt(Trajectory{}, 0).has_value());
}

TEST(TrajectoryTest, PathLengthSumsSegments) {
  EXPECT_NEAR(PathLength(Straight()), 5.0, 1e-12);
  EXPECT_EQ(PathLength(Trajectory{}), 0.0);
}

TEST(TrajectoryTest, TransformedMovesEveryPoseKeepingTimes) {
  const Trajectory moved = Transformed(SE2(1.0, 2.0, kPi / 2), Straight());
  ASSERT_EQ(moved.size(), 3u);
  EXPECT_EQ(moved[1].t_ns, kNanosecondsPerSecond);
  // (2, 0) turned by 90 degrees and shifted by (1, 2): (1, 4).
  EXPECT_NEAR(moved[1].T_map_vehicle.x(), 1.0, 1e-12);
  EXPECT_NEAR(moved[1].T_map_vehicle.y(), 4.0, 1e-12);
  EXPECT_NEAR(moved[1].T_map_vehicle.yaw(), kPi / 2 + 0.2, 1e-12);
}

TEST(TrajectoryTest, AppendOrReplaceLastKeepsTimesStrictlyIncreasing) {
  Trajectory t;
  EXPECT_TRUE(AppendOrReplaceLast(&t, {10, SE2(1.0, 0.0, 0.0)}));
  EXPECT_FALSE(AppendOrReplaceLast(&t, {10, SE2(2.0, 0.0, 0.0)}));
  EXPECT_TRUE(AppendOrReplaceLast(&t, {20, SE2(3.0, 0.0, 0.0)}));
  ASSERT_EQ(t.size(), 2u);
  EXPECT_DOUBLE_EQ(t[0].T_map_vehicle.x(), 2.0);  // the later estimate at t = 10
  EXPECT_EQ(t[1].t_ns, 20);
}

TEST(TimeTest, SecondsRoundTrip) {
  EXPECT_EQ(FromSeconds(1.5), 1'500'000'000);
  EXPECT_DOUBLE_EQ(ToSeconds(FromSeconds(123.456789)), 123.456789);
}

}  // namespace
}  // namespace parkslam
