#include "parkslam/control/trace.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "parkslam/common/angles.h"

namespace parkslam::control {
namespace {

// Points along a circle of radius_m about the origin, counter-clockwise from
// angle 0 over `turns` turns, about spacing_m apart.
std::vector<Eigen::Vector2d> Circle(double radius_m, double turns, double spacing_m = 0.1) {
  const int n = static_cast<int>(std::ceil(2.0 * kPi * radius_m * turns / spacing_m));
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i <= n; ++i) {
    const double angle = 2.0 * kPi * turns * i / n;
    points.emplace_back(radius_m * std::cos(angle), radius_m * std::sin(angle));
  }
  return points;
}

TEST(TraceTest, BuildsFromTrajectoryDroppingClosePoints) {
  Trajectory trajectory;
  const std::vector<double> xs = {0.0, 0.02, 0.5, 0.5, 0.53, 1.0, 2.0, 2.01};
  for (size_t i = 0; i < xs.size(); ++i) {
    trajectory.push_back({static_cast<TimeNs>(i), SE2(xs[i], 0.0, 0.0)});
  }
  const Trace trace(trajectory);
  ASSERT_EQ(trace.points_m().size(), 4u);  // 0, 0.5, 1.0 and the true end 2.01
  EXPECT_DOUBLE_EQ(trace.points_m().back().x(), 2.01);
  EXPECT_NEAR(trace.length_m(), 2.01, 1e-12);
}

TEST(TraceTest, RejectsTooFewPointsOrTooShort) {
  EXPECT_THROW(Trace(std::vector<Eigen::Vector2d>{{0.0, 0.0}, {0.01, 0.0}}), std::invalid_argument);
  EXPECT_THROW(Trace(std::vector<Eigen::Vector2d>{{0.0, 0.0}, {0.99, 0.0}}), std::invalid_argument);
  EXPECT_NO_THROW(Trace(std::vector<Eigen::Vector2d>{{0.0, 0.0}, {1.01, 0.0}}));
  EXPECT_THROW(Trace(Trajectory{}), std::invalid_argument);
}

TEST(TraceTest, PointAtInterpolatesAndClamps) {
  const Trace trace(std::vector<Eigen::Vector2d>{{0.0, 0.0}, {10.0, 0.0}, {10.0, 5.0}});
  EXPECT_NEAR((trace.PointAt(3.5) - Eigen::Vector2d(3.5, 0.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((trace.PointAt(12.0) - Eigen::Vector2d(10.0, 2.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((trace.PointAt(-1.0) - Eigen::Vector2d(0.0, 0.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((trace.PointAt(99.0) - Eigen::Vector2d(10.0, 5.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(trace.HeadingAt(5.0), 0.0, 1e-12);
  EXPECT_NEAR(trace.HeadingAt(11.0), kPi / 2.0, 1e-12);
}

TEST(TraceTest, ProjectsOntoStraightLineWithSignedLateral) {
  const Trace trace(std::vector<Eigen::Vector2d>{{0.0, 0.0}, {20.0, 0.0}});
  const Trace::Projection left = trace.ProjectGlobal({7.0, 0.4});
  EXPECT_NEAR(left.s_m, 7.0, 1e-12);
  EXPECT_NEAR(left.lateral_m, 0.4, 1e-12);
  EXPECT_NEAR((left.point - Eigen::Vector2d(7.0, 0.0)).norm(), 0.0, 1e-12);
  const Trace::Projection right = trace.ProjectGlobal({7.0, -0.3});
  EXPECT_NEAR(right.lateral_m, -0.3, 1e-12);
}

TEST(TraceTest, LateralSignFollowsDirectionOfTravel) {
  // Driving towards -x, the +y side is on the right.
  const Trace trace(std::vector<Eigen::Vector2d>{{20.0, 0.0}, {0.0, 0.0}});
  EXPECT_NEAR(trace.ProjectGlobal({7.0, 0.4}).lateral_m, -0.4, 1e-12);
  EXPECT_NEAR(trace.ProjectGlobal({7.0, -0.4}).lateral_m, 0.4, 1e-12);
}

TEST(TraceTest, ProjectsAroundCorner) {
  // East 10 m, then north 10 m: a left turn at (10, 0).
  const Trace trace(std::vector<Eigen::Vector2d>{{0.0, 0.0}, {10.0, 0.0}, {10.0, 10.0}});
  // Outside the corner: the corner itself, on the right.
  const Trace::Projection outside = trace.ProjectGlobal({10.3, -0.4});
  EXPECT_NEAR(outside.s_m, 10.0, 1e-12);
  EXPECT_NEAR(outside.lateral_m, -0.5, 1e-12);
  // Inside the corner, nearer the second leg.
  const Trace::Projection inside = trace.ProjectGlobal({9.8, 1.0});
  EXPECT_NEAR(inside.s_m, 11.0, 1e-12);
  EXPECT_NEAR(inside.lateral_m, 0.2, 1e-12);
  // On the second leg, right of it.
  const Trace::Projection leg = trace.ProjectGlobal({10.25, 6.0});
  EXPECT_NEAR(leg.s_m, 16.0, 1e-12);
  EXPECT_NEAR(leg.lateral_m, -0.25, 1e-12);
}

TEST(TraceTest, PerpendicularOffsetBeyondTheEnd) {
  const Trace trace(std::vector<Eigen::Vector2d>{{0.0, 0.0}, {10.0, 0.0}});
  const Trace::Projection past = trace.ProjectGlobal({10.5, 0.1});
  EXPECT_NEAR(past.s_m, 10.0, 1e-12);
  EXPECT_NEAR(past.lateral_m, 0.1, 1e-12);
}

TEST(TraceTest, LoopPassedTwiceIsFollowedInOrderWithTheHint) {
  const Trace trace(Circle(10.0, 2.0));
  const double lap_m = trace.length_m() / 2.0;
  // A point just inside the circle at angle 90 degrees: a quarter lap into
  // either pass.
  const Eigen::Vector2d p(0.0, 9.9);
  const Trace::Projection first = trace.Project(p, 0.25 * lap_m + 2.0, 5.0);
  EXPECT_NEAR(first.s_m, 0.25 * lap_m, 0.01);
  EXPECT_NEAR(first.lateral_m, 0.1, 1e-3);
  const Trace::Projection second = trace.Project(p, 1.25 * lap_m - 3.0, 5.0);
  EXPECT_NEAR(second.s_m, 1.25 * lap_m, 0.01);
  EXPECT_NEAR(second.lateral_m, 0.1, 1e-3);
}

TEST(TraceTest, ProjectionStaysInsideTheWindow) {
  const Trace trace(std::vector<Eigen::Vector2d>{{0.0, 0.0}, {20.0, 0.0}});
  const Trace::Projection clamped = trace.Project({15.0, 0.0}, 5.0, 4.0);
  EXPECT_NEAR(clamped.s_m, 9.0, 1e-12);
  const Trace::Projection inside = trace.Project({15.0, 0.0}, 5.0, 10.5);
  EXPECT_NEAR(inside.s_m, 15.0, 1e-12);
}

TEST(TraceTest, ArcLengthAndCurvatureOfCircle) {
  const Trace trace(Circle(5.0, 1.0));
  EXPECT_NEAR(trace.length_m(), 2.0 * kPi * 5.0, 0.01);
  for (double s = 1.0; s <= trace.length_m() - 1.0; s += 0.37) {
    EXPECT_NEAR(trace.CurvatureAt(s), 0.2, 0.2 * 0.05) << "s = " << s;
  }
  // Clockwise: negative curvature.
  std::vector<Eigen::Vector2d> clockwise = Circle(5.0, 1.0);
  for (Eigen::Vector2d& p : clockwise) p.y() = -p.y();
  EXPECT_NEAR(Trace(clockwise).CurvatureAt(10.0), -0.2, 0.2 * 0.05);
}

TEST(TraceTest, CurvatureOfStraightLineIsZeroAndEndsAreDefined) {
  const Trace line(std::vector<Eigen::Vector2d>{{0.0, 0.0}, {5.0, 5.0}});
  EXPECT_NEAR(line.CurvatureAt(2.0), 0.0, 1e-12);
  const Trace circle(Circle(5.0, 0.5));
  EXPECT_NEAR(circle.CurvatureAt(0.0), 0.2, 0.2 * 0.05);
  EXPECT_NEAR(circle.CurvatureAt(circle.length_m()), 0.2, 0.2 * 0.05);
}

}  // namespace
}  // namespace parkslam::control
