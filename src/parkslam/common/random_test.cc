#include "parkslam/common/random.h"

#include <gtest/gtest.h>

#include <cmath>

namespace parkslam {
namespace {

TEST(RandomTest, SameSeedSameSequence) {
  Random a(42), b(42);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(a.Gaussian(), b.Gaussian());
}

TEST(RandomTest, DerivedStreamsDiffer) {
  Random a = Random::Derive(7, 1), b = Random::Derive(7, 2);
  EXPECT_NE(a.Uniform(), b.Uniform());
}

TEST(RandomTest, GaussianMomentsMatch) {
  Random r(3);
  const int n = 200000;
  double sum = 0, sum2 = 0;
  for (int i = 0; i < n; ++i) {
    const double x = r.Gaussian(2.0);
    sum += x;
    sum2 += x * x;
  }
  const double mean = sum / n;
  EXPECT_NEAR(mean, 0.0, 0.02);
  EXPECT_NEAR(std::sqrt(sum2 / n - mean * mean), 2.0, 0.02);
}

TEST(RandomTest, PoissonMeanMatches) {
  Random r(5);
  const int n = 100000;
  long total = 0;
  for (int i = 0; i < n; ++i) total += r.Poisson(0.3);
  EXPECT_NEAR(static_cast<double>(total) / n, 0.3, 0.01);
}

TEST(RandomTest, UniformStaysInRange) {
  Random r(9);
  for (int i = 0; i < 10000; ++i) {
    const double u = r.Uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    ASSERT_LT(r.Index(7), 7u);
  }
}

}  // namespace
}  // namespace parkslam
