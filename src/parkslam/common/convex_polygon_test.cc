#include "parkslam/common/convex_polygon.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace parkslam {
namespace {

std::vector<Eigen::Vector2d> Box(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

TEST(ConvexPolygonTest, AreaIsTheSameEitherWayRound) {
  std::vector<Eigen::Vector2d> box = Box(0, 0, 2.5, 5.3);
  EXPECT_NEAR(PolygonArea(box), 13.25, 1e-12);
  std::reverse(box.begin(), box.end());
  EXPECT_NEAR(PolygonArea(box), 13.25, 1e-12);
}

TEST(ConvexPolygonTest, OverlapOfBoxes) {
  EXPECT_NEAR(ConvexOverlapArea(Box(0, 0, 2, 2), Box(1, 1, 3, 3)), 1.0, 1e-12);
  EXPECT_NEAR(ConvexOverlapArea(Box(0, 0, 2, 2), Box(0.5, 0.5, 1, 1)), 0.25, 1e-12);  // inside
  EXPECT_NEAR(ConvexOverlapArea(Box(0, 0, 2, 2), Box(2, 0, 4, 2)), 0.0, 1e-12);       // touching
  EXPECT_NEAR(ConvexOverlapArea(Box(0, 0, 2, 2), Box(5, 5, 6, 6)), 0.0, 1e-12);
  std::vector<Eigen::Vector2d> clockwise = Box(1, 1, 3, 3);
  std::reverse(clockwise.begin(), clockwise.end());
  EXPECT_NEAR(ConvexOverlapArea(Box(0, 0, 2, 2), clockwise), 1.0, 1e-12);
  EXPECT_NEAR(ConvexOverlapArea(clockwise, Box(0, 0, 2, 2)), 1.0, 1e-12);
  EXPECT_EQ(ConvexOverlapArea({{0, 0}, {1, 1}}, Box(0, 0, 2, 2)), 0.0);
}

TEST(ConvexPolygonTest, OverlapOfARotatedSquare) {
  // A unit square turned 45 degrees and centred on the corner (1, 1) of
  // the box [0, 1]^2 covers a quarter of itself there: a right triangle
  // with legs sqrt(1/2), of area 1/4.
  const double h = std::sqrt(0.5);
  const std::vector<Eigen::Vector2d> diamond = {{1, 1 - h}, {1 + h, 1}, {1, 1 + h}, {1 - h, 1}};
  EXPECT_NEAR(ConvexOverlapArea(Box(0, 0, 1, 1), diamond), 0.25, 1e-12);
  EXPECT_NEAR(ConvexOverlapArea(diamond, Box(0, 0, 1, 1)), 0.25, 1e-12);
}

}  // namespace
}  // namespace parkslam
