#include "parkslam/render/sensor_noise.h"

#include <gtest/gtest.h>

namespace parkslam::render {
namespace {

struct Moments {
  double mean, variance;
};

Moments NoiseMoments(const cv::Mat& noisy, double base) {
  double sum = 0.0, sum2 = 0.0;
  for (int r = 0; r < noisy.rows; ++r) {
    for (int c = 0; c < noisy.cols; ++c) {
      const double d = noisy.at<std::uint8_t>(r, c) - base;
      sum += d;
      sum2 += d * d;
    }
  }
  const double n = static_cast<double>(noisy.total());
  return {sum / n, sum2 / n - (sum / n) * (sum / n)};
}

TEST(SensorNoiseTest, HasZeroMeanAndTheRequestedVariance) {
  for (double sigma : {2.0, 5.0, 12.0}) {
    cv::Mat image(480, 640, CV_8UC1, cv::Scalar(128));
    SensorNoise(sigma).Apply(42, &image);
    const Moments m = NoiseMoments(image, 128.0);
    EXPECT_NEAR(m.mean, 0.0, 0.05) << sigma;
    // Rounding to whole grey levels adds 1/12.
    EXPECT_NEAR(m.variance, sigma * sigma + 1.0 / 12, 0.03 * sigma * sigma) << sigma;
  }
}

TEST(SensorNoiseTest, SameSeedSameNoiseOtherSeedOtherNoise) {
  cv::Mat a(100, 101, CV_8UC1, cv::Scalar(100)), b = a.clone(), c = a.clone();
  const SensorNoise noise(3.0);
  noise.Apply(7, &a);
  noise.Apply(7, &b);
  noise.Apply(8, &c);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a, c, cv::NORM_L1), 100.0 * 101.0);
}

TEST(SensorNoiseTest, ZeroSigmaLeavesTheImageAndClampsAtTheEnds) {
  cv::Mat image(10, 10, CV_8UC1, cv::Scalar(77));
  SensorNoise(0.0).Apply(1, &image);
  EXPECT_EQ(cv::countNonZero(image != 77), 0);
  cv::Mat black(50, 50, CV_8UC1, cv::Scalar(0));
  SensorNoise(10.0).Apply(1, &black);
  double lo = 0.0, hi = 0.0;
  cv::minMaxLoc(black, &lo, &hi);
  EXPECT_EQ(lo, 0.0);
  EXPECT_GT(hi, 10.0);
}

}  // namespace
}  // namespace parkslam::render
