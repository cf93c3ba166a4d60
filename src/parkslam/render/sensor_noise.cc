#include "parkslam/render/sensor_noise.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace parkslam::render {
namespace {

constexpr int kTableBits = 12;
constexpr int kTableSize = 1 << kTableBits;
constexpr int kFractionBits = 8;
constexpr int kPerDraw = 64 / kTableBits;

// The standard normal quantile (Acklam's rational approximation, relative
// error below 1.2e-9).
double NormalQuantile(double p) {
  static constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,
                                 -2.759285104469687e+02, 1.383577518672690e+02,
                                 -3.066479806614716e+01, 2.506628277459239e+00};
  static constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02,
                                 -1.556989798598866e+02, 6.680131188771972e+01,
                                 -1.328068155288572e+01};
  static constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01,
                                 -2.400758277161838e+00, -2.549732539343734e+00,
                                 4.374664141464968e+00,  2.938163982698783e+00};
  static constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01,
                                 2.445134137142996e+00, 3.754408661907416e+00};
  constexpr double kLow = 0.02425;
  if (p < kLow || p > 1 - kLow) {
    const double q = std::sqrt(-2 * std::log(p < kLow ? p : 1 - p));
    const double x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
                     ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
    return p < kLow ? x : -x;
  }
  const double q = p - 0.5, r = q * q;
  return (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
         (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
}

}  // namespace

SensorNoise::SensorNoise(double sigma_grey) : sigma_grey_(sigma_grey), table_(kTableSize) {
  if (!(sigma_grey >= 0.0)) throw std::invalid_argument("noise sigma must be non-negative");
  for (int k = 0; k < kTableSize; ++k) {
    const double p = (k + 0.5) / kTableSize;
    table_[static_cast<size_t>(k)] = static_cast<std::int32_t>(
        std::lround(sigma_grey * NormalQuantile(p) * (1 << kFractionBits)));
  }
}

void SensorNoise::Apply(std::uint64_t seed, cv::Mat* image) const {
  if (sigma_grey_ <= 0.0) return;
  if (image->type() != CV_8UC1 || !image->isContinuous()) {
    throw std::invalid_argument("SensorNoise needs a continuous CV_8UC1 image");
  }
  std::uint64_t x = seed | 1u;
  const size_t n = image->total();
  std::uint8_t* p = image->ptr<std::uint8_t>(0);
  for (size_t i = 0; i < n; i += kPerDraw) {
    x ^= x >> 12;
    x ^= x << 25;
    x ^= x >> 27;
    std::uint64_t bits = x * 0x2545F4914F6CDD1Dull;
    const size_t end = std::min(n, i + kPerDraw);
    for (size_t j = i; j < end; ++j, bits >>= kTableBits) {
      const std::int32_t v = (static_cast<std::int32_t>(p[j]) << kFractionBits) +
                             table_[bits & (kTableSize - 1)] + (1 << (kFractionBits - 1));
      p[j] = static_cast<std::uint8_t>(std::clamp(v >> kFractionBits, 0, 255));
    }
  }
}

}  // namespace parkslam::render
