#ifndef PARKSLAM_RENDER_SENSOR_NOISE_H_
#define PARKSLAM_RENDER_SENSOR_NOISE_H_

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace parkslam::render {

// Additive Gaussian sensor noise for 8-bit images, fast enough to run on
// every frame: each pixel takes one of 4096 equally likely Gaussian
// quantiles (so the tails stop at 3.7 sigma), picked by 12 bits of a
// xorshift64* stream, five pixels per draw. Deterministic by seed.
class SensorNoise {
 public:
  explicit SensorNoise(double sigma_grey);

  // Adds noise to a continuous CV_8UC1 image, rounding and clamping to 0..255.
  void Apply(std::uint64_t seed, cv::Mat* image) const;

 private:
  double sigma_grey_;
  std::vector<std::int32_t> table_;  // quantiles in 1/256 grey level
};

}  // namespace parkslam::render

#endif  // PARKSLAM_RENDER_SENSOR_NOISE_H_
