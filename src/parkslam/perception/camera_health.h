#ifndef PARKSLAM_PERCEPTION_CAMERA_HEALTH_H_
#define PARKSLAM_PERCEPTION_CAMERA_HEALTH_H_

// Cameras that fail (docs/robustness.md, "Sensor faults"): an image that is
// black (a dead sensor, a covered lens, a lost link that a driver fills with
// zeros) or frozen (the same bytes as the camera's previous image: a real
// sensor's noise never repeats). The front end leaves such a camera out of
// the top view and the tag detector until its images are healthy again.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "parkslam/sensor/sensor_data.h"

namespace parkslam::perception {

enum class CameraHealth { kOk, kBlack, kFrozen };
const char* ToString(CameraHealth health);

struct CameraHealthOptions {
  // Black: the sampled pixels' mean and standard deviation (grey levels)
  // both below these.
  double black_mean_max = 12.0;
  double black_stddev_max = 4.0;
  // Every sample_stride-th pixel of every sample_stride-th row is read.
  int sample_stride = 7;
};

class CameraHealthMonitor {
 public:
  explicit CameraHealthMonitor(const CameraHealthOptions& options = {}) : options_(options) {}

  // The health of each image of the frame (same order as frame.cameras),
  // against the same camera's previous image.
  std::vector<CameraHealth> Check(const CameraFrame& frame);

  // Images judged black or frozen so far, per camera.
  const std::map<std::string, int>& black_images() const { return black_; }
  const std::map<std::string, int>& frozen_images() const { return frozen_; }

 private:
  CameraHealthOptions options_;
  std::map<std::string, std::uint64_t> last_fingerprint_;
  std::map<std::string, int> black_, frozen_;
};

}  // namespace parkslam::perception

#endif  // PARKSLAM_PERCEPTION_CAMERA_HEALTH_H_
