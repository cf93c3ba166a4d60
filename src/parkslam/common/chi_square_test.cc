#include "parkslam/common/chi_square.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace parkslam {
namespace {

// True when value is within `fraction` of expected, relative.
::testing::AssertionResult WithinRelative(double value, double expected, double fraction) {
  if (std::abs(value - expected) <= fraction * std::abs(expected)) {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure()
         << value << " is not within " << 100.0 * fraction << "% of " << expected;
}

TEST(RegularizedLowerGammaTest, MatchesClosedFormForAOne) {
  // P(1, x) = 1 - exp(-x).
  for (double x : {0.01, 0.5, 1.0, 2.0, 5.0, 30.0}) {
    EXPECT_NEAR(RegularizedLowerGamma(1.0, x), 1.0 - std::exp(-x), 1e-13) << x;
  }
}

TEST(RegularizedLowerGammaTest, MatchesErfForAOneHalf) {
  // P(1/2, x) = erf(sqrt(x)).
  for (double x : {0.001, 0.3, 1.5, 4.0, 12.0}) {
    EXPECT_NEAR(RegularizedLowerGamma(0.5, x), std::erf(std::sqrt(x)), 1e-13) << x;
  }
}

TEST(ChiSquareQuantileTest, ThreeDof) {
  EXPECT_TRUE(WithinRelative(ChiSquareQuantile(0.975, 3), 9.348, 0.0005));
  EXPECT_TRUE(WithinRelative(ChiSquareQuantile(0.025, 3), 0.2158, 0.0005));
}

TEST(ChiSquareQuantileTest, TwoDofIsClosedForm) {
  // For 2 dof the CDF is 1 - exp(-x / 2).
  EXPECT_TRUE(WithinRelative(ChiSquareQuantile(0.95, 2), 5.991, 0.0005));
  EXPECT_NEAR(ChiSquareQuantile(0.95, 2), -2.0 * std::log(0.05), 1e-9);
}

TEST(ChiSquareQuantileTest, SixtyDof) {
  EXPECT_TRUE(WithinRelative(ChiSquareQuantile(0.975, 60), 83.30, 0.0005));
  EXPECT_TRUE(WithinRelative(ChiSquareQuantile(0.025, 60), 40.48, 0.0005));
}

TEST(ChiSquareQuantileTest, OneDofTails) {
  // chi2 with 1 dof is a squared standard normal: quantile p is z^2 with z
  // the (1 + p) / 2 normal quantile (z_0.9995 = 3.290527, z_0.5005 =
  // 0.00125331).
  EXPECT_TRUE(WithinRelative(ChiSquareQuantile(0.999, 1), 10.82757, 1e-5));
  EXPECT_TRUE(WithinRelative(ChiSquareQuantile(0.001, 1), 1.570796e-6, 1e-4));
}

TEST(ChiSquareQuantileTest, TenThousandDof) {
  // Reference values from mpmath's regularised incomplete gamma (30 digits).
  EXPECT_TRUE(WithinRelative(ChiSquareQuantile(0.975, 10000), 10279.0702, 1e-7));
  EXPECT_TRUE(WithinRelative(ChiSquareQuantile(0.001, 10000), 9568.66850, 1e-7));
}

TEST(ChiSquareQuantileTest, RoundTripsThroughTheCdf) {
  for (int dof : {1, 2, 5, 17, 300, 5000}) {
    for (double p : {0.001, 0.05, 0.5, 0.9, 0.999}) {
      const double x = ChiSquareQuantile(p, dof);
      EXPECT_NEAR(RegularizedLowerGamma(0.5 * dof, 0.5 * x), p, 1e-10)
          << "dof " << dof << " p " << p;
    }
  }
}

TEST(ChiSquareQuantileTest, RejectsInvalidArguments) {
  EXPECT_THROW(ChiSquareQuantile(0.0, 3), std::invalid_argument);
  EXPECT_THROW(ChiSquareQuantile(1.0, 3), std::invalid_argument);
  EXPECT_THROW(ChiSquareQuantile(0.5, 0), std::invalid_argument);
}

}  // namespace
}  // namespace parkslam
