#include "parkslam/perception/camera_health.h"

#include <algorithm>
#include <cmath>

namespace parkslam::perception {

const char* ToString(CameraHealth health) {
  switch (health) {
    case CameraHealth::kOk:
      return "ok";
    case CameraHealth::kBlack:
      return "black";
    case CameraHealth::kFrozen:
      return "frozen";
  }
  return "?";
}

std::vector<CameraHealth> CameraHealthMonitor::Check(const CameraFrame& frame) {
  std::vector<CameraHealth> health(frame.cameras.size(), CameraHealth::kOk);
  const int stride = std::max(1, options_.sample_stride);
  for (std::size_t k = 0; k < frame.cameras.size() && k < frame.images.size(); ++k) {
    const ImagePlane& image = frame.images[k];
    if (image.pixels == nullptr || image.width <= 0 || image.height <= 0) continue;
    const std::vector<std::uint8_t>& pixels = *image.pixels;
    // FNV-1a over the samples, with their mean and variance.
    std::uint64_t fingerprint = 14695981039346656037ULL;
    double sum = 0.0, sum2 = 0.0;
    std::size_t n = 0;
    for (int v = 0; v < image.height; v += stride) {
      const std::size_t row = static_cast<std::size_t>(v) * static_cast<std::size_t>(image.width);
      for (int u = v % stride; u < image.width; u += stride) {
        const std::uint8_t p = pixels[row + static_cast<std::size_t>(u)];
        fingerprint = (fingerprint ^ p) * 1099511628211ULL;
        sum += p;
        sum2 += static_cast<double>(p) * p;
        ++n;
      }
    }
    const double mean = sum / static_cast<double>(n);
    const double stddev = std::sqrt(std::max(0.0, sum2 / static_cast<double>(n) - mean * mean));
    const std::string& name = frame.cameras[k];
    const auto last = last_fingerprint_.find(name);
    if (mean < options_.black_mean_max && stddev < options_.black_stddev_max) {
      health[k] = CameraHealth::kBlack;
      ++black_[name];
    } else if (last != last_fingerprint_.end() && last->second == fingerprint) {
      health[k] = CameraHealth::kFrozen;
      ++frozen_[name];
    }
    last_fingerprint_[name] = fingerprint;
  }
  return health;
}

}  // namespace parkslam::perception
