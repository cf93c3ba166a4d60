#ifndef PARKSLAM_CAMERA_CAMERA_NAMES_H_
#define PARKSLAM_CAMERA_CAMERA_NAMES_H_

// The rig's camera names (paper III-A and III-B): four fisheyes fused into
// the top view, in the order the fusion takes them, and the front camera
// that reads AprilTags. A rig file and a dataset's images use these names.

#include <string>
#include <vector>

namespace parkslam::camera {

inline const std::vector<std::string>& FisheyeCameraNames() {
  static const std::vector<std::string> names{"front", "rear", "left", "right"};
  return names;
}

inline constexpr char kTagCameraName[] = "front_mono";

// The four fisheyes, then the tag camera.
inline const std::vector<std::string>& AllCameraNames() {
  static const std::vector<std::string> names{"front", "rear", "left", "right", kTagCameraName};
  return names;
}

}  // namespace parkslam::camera

#endif  // PARKSLAM_CAMERA_CAMERA_NAMES_H_
