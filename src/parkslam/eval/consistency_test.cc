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
  // White frames are worth about as many independent ones.
  EXPECT_GT(good.effective_frames, 3000);
  EXPECT_LT(good.effective_frames, 5000);
}

// White noise has an autocorrelation time of 1; an AR(1) series
// x_k = a x_(k-1) + e_k has (1 + a) / (1 - a): 19 for a = 0.9.
TEST(IntegratedAutocorrelationTimeTest, WhiteAndAutoregressiveSeries) {
  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  std::vector<double> white, ar1;
  double x = 0.0;
  for (int k = 0; k < 50000; ++k) {
    white.push_back(normal(rng));
    x = 0.9 * x + normal(rng);
    ar1.push_back(x);
  }
  EXPECT_NEAR(IntegratedAutocorrelationTime(white), 1.0, 0.1);
  EXPECT_NEAR(IntegratedAutocorrelationTime(ar1), 19.0, 2.5);
  EXPECT_EQ(IntegratedAutocorrelationTime({}), 1.0);
  EXPECT_EQ(IntegratedAutocorrelationTime({2.0, 2.0, 2.0}), 1.0);
}

// A correlated drive: the same chi-square(3) NEES held for 20 frames at a
// time is worth about a twentieth of its frames, and its band widens so.
TEST(SummarizeNeesTest, CorrelatedFramesWidenTheEffectiveBand) {
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  std::vector<double> held;
  for (int k = 0; k < 400; ++k) {
    double v = 0.0;
    for (int d = 0; d < 3; ++d) v += std::pow(normal(rng), 2);
    held.insert(held.end(), 20, v);
  }
  const NeesSummary s = SummarizeNees(held, 3);
  EXPECT_EQ(s.frames, 8000);
  EXPECT_GT(s.effective_frames, 250);
  EXPECT_LT(s.effective_frames, 650);
  // About sqrt(20) times wider.
  const double strict = s.mean_band.upper - s.mean_band.lower;
  const double effective = s.effective_mean_band.upper - s.effective_mean_band.lower;
  EXPECT_GT(effective, 3.5 * strict);
  EXPECT_LT(effective, 5.5 * strict);
  EXPECT_LT(s.effective_mean_band.lower, s.mean_band.lower);
}

}  // namespace
}  // namespace parkslam::eval
