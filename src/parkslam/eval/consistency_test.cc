#include "parkslam/eval/consistency.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace parkslam::eval {
namespace {

// True when value is within `fraction` of expected, relative.
::testing::AssertionResult WithinRelative(double value, double expected, double fraction) {
  if (std::abs(value - expected) <= fraction * std::abs(expected)) {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure()
         << value << " is not within " << 100.0 * fraction << "% of " << expected;
}

TEST(NeesTest, DiagonalCovariance) {
  const Eigen::Vector3d error(0.2, -0.3, 0.05);
  const Eigen::Matrix3d covariance = Eigen::Vector3d(0.04, 0.09, 0.0025).asDiagonal();
  // 0.04/0.04 + 0.09/0.09 + 0.0025/0.0025
  EXPECT_NEAR(Nees(error, covariance), 3.0, 1e-12);
}

TEST(NeesTest, CorrelatedCovariance) {
  Eigen::Matrix3d covariance;
  covariance << 2.0, 1.0, 0.0,  //
      1.0, 2.0, 0.0,            //
      0.0, 0.0, 4.0;
  // The inverse of the upper block is [2 -1; -1 2] / 3.
  const Eigen::Vector3d error(1.0, 1.0, 2.0);
  EXPECT_NEAR(Nees(error, covariance), 2.0 / 3.0 + 1.0, 1e-12);
}

TEST(AverageNeesBandTest, SingleRunIsTheChiSquareInterval) {
  const NeesBand band = AverageNeesBand(3, 1);
  EXPECT_TRUE(WithinRelative(band.lower, 0.2158, 0.005));
  EXPECT_TRUE(WithinRelative(band.upper, 9.348, 0.005));
}

TEST(AverageNeesBandTest, TwentyRunsOfThreeDof) {
  // chi2 with 60 dof, divided by the 20 runs.
  const NeesBand band = AverageNeesBand(3, 20);
  EXPECT_TRUE(WithinRelative(band.lower, 40.48 / 20.0, 0.005));
  EXPECT_TRUE(WithinRelative(band.upper, 83.30 / 20.0, 0.005));
}

TEST(AverageNeesBandTest, NarrowsAroundDofWithMoreRuns) {
  const NeesBand few = AverageNeesBand(3, 5);
  const NeesBand many = AverageNeesBand(3, 500);
  EXPECT_LT(many.upper - many.lower, few.upper - few.lower);
  EXPECT_LT(many.lower, 3.0);
  EXPECT_GT(many.upper, 3.0);
}

TEST(AverageNeesBandTest, RejectsInvalidArguments) {
  EXPECT_THROW(AverageNeesBand(0, 1), std::invalid_argument);
  EXPECT_THROW(AverageNeesBand(3, 0), std::invalid_argument);
  EXPECT_THROW(AverageNeesBand(3, 1, 1.0), std::invalid_argument);
}

// A consistent filter's NEES of 3 dof is chi-square(3): drawn as the sum of
// three squared standard normals, its summary sits in both bands; the same
// errors against a covariance four times too small do not.
TEST(SummarizeNeesTest, ConsistentAndOverconfidentFilters) {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  std::vector<double> consistent, overconfident;
  for (int k = 0; k < 4000; ++k) {
    double v = 0.0;
    for (int d = 0; d < 3; ++d) v += std::pow(normal(rng), 2);
    consistent.push_back(v);
    overconfident.push_back(4.0 * v);
  }
  const NeesSummary good = SummarizeNees(consistent, 3);
  EXPECT_EQ(good.frames, 4000);
  EXPECT_GT(good.mean, good.mean_band.lower);
  EXPECT_LT(good.mean, good.mean_band.upper);
  EXPECT_NEAR(good.median, 2.366, 0.15);  // chi-square(3) median
  EXPECT_NEAR(good.share_inside_frame_band, 0.95, 0.015);
  const NeesSummary bad = SummarizeNees(overconfident, 3);
  EXPECT_GT(bad.mean, bad.mean_band.upper);
  EXPECT_LT(bad.share_inside_frame_band, 0.8);
  EXPECT_EQ(SummarizeNees({}, 3).frames, 0);
}

}  // namespace
}  // namespace parkslam::eval
