#include "parkslam/common/alignment.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "parkslam/common/angles.h"
#include "parkslam/common/random.h"

namespace parkslam {
namespace {

std::vector<Eigen::Vector2d> RandomPoints(Random* random, int count) {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < count; ++i) {
    points.emplace_back(random->Uniform(-30.0, 30.0), random->Uniform(-20.0, 20.0));
  }
  return points;
}

std::vector<Eigen::Vector2d> Transform(const SE2& T, const std::vector<Eigen::Vector2d>& points) {
  std::vector<Eigen::Vector2d> out;
  for (const Eigen::Vector2d& p : points) out.push_back(T * p);
  return out;
}

TEST(AlignPointSetsTest, RecoversKnownTransformWithoutNoise) {
  Random random(7);
  const std::vector<Eigen::Vector2d> source = RandomPoints(&random, 50);
  const SE2 T_target_source(12.5, -4.0, DegToRad(133.0));
  const SE2 T = AlignPointSets(source, Transform(T_target_source, source));
  EXPECT_NEAR(T.x(), 12.5, 1e-9);
  EXPECT_NEAR(T.y(), -4.0, 1e-9);
  EXPECT_NEAR(AngleDiff(T.yaw(), DegToRad(133.0)), 0.0, 1e-12);
  for (const Eigen::Vector2d& p : source) {
    EXPECT_LT((T * p - T_target_source * p).norm(), 1e-3);
  }
}

TEST(AlignPointSetsTest, RecoversTransformNearPiWithTwoPoints) {
  const std::vector<Eigen::Vector2d> source{{0.0, 0.0}, {10.0, 0.0}};
  const SE2 T_target_source(-3.0, 2.0, kPi);
  const SE2 T = AlignPointSets(source, Transform(T_target_source, source));
  EXPECT_NEAR(T.x(), -3.0, 1e-9);
  EXPECT_NEAR(T.y(), 2.0, 1e-9);
  EXPECT_NEAR(AngleDiff(T.yaw(), kPi), 0.0, 1e-12);
}

TEST(AlignPointSetsTest, RecoversTransformFromNoisyPoints) {
  Random random(42);
  const std::vector<Eigen::Vector2d> source = RandomPoints(&random, 400);
  const SE2 T_target_source(-7.0, 3.0, DegToRad(-35.0));
  std::vector<Eigen::Vector2d> target = Transform(T_target_source, source);
  for (Eigen::Vector2d& p : target) {
    p += Eigen::Vector2d(random.Gaussian(0.05), random.Gaussian(0.05));
  }
  const SE2 T = AlignPointSets(source, target);
  // 0.05 m noise on 400 points: centroid error ~2.5 mm, yaw error ~0.1 mrad.
  EXPECT_NEAR(T.x(), -7.0, 0.015);
  EXPECT_NEAR(T.y(), 3.0, 0.015);
  EXPECT_NEAR(AngleDiff(T.yaw(), DegToRad(-35.0)), 0.0, 1e-3);
}

TEST(AlignPointSetsTest, ThrowsOnUnequalCounts) {
  const std::vector<Eigen::Vector2d> source{{0.0, 0.0}, {1.0, 0.0}};
  const std::vector<Eigen::Vector2d> target{{0.0, 0.0}, {1.0, 0.0}, {2.0, 0.0}};
  EXPECT_THROW(AlignPointSets(source, target), std::invalid_argument);
}

TEST(AlignPointSetsTest, ThrowsOnSinglePoint) {
  const std::vector<Eigen::Vector2d> one{{1.0, 2.0}};
  EXPECT_THROW(AlignPointSets(one, one), std::invalid_argument);
}

}  // namespace
}  // namespace parkslam
