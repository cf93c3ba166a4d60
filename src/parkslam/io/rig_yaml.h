#ifndef PARKSLAM_IO_RIG_YAML_H_
#define PARKSLAM_IO_RIG_YAML_H_

// The project's camera rig file (docs/cameras.md):
//
//   cameras:
//     - name: front
//       model: fisheye            # or pinhole
//       width: 640
//       height: 480
//       fx: 180.0
//       fy: 180.0
//       cx: 319.5
//       cy: 239.5
//       distortion: [k1, k2, k3, k4]   # pinhole: [k1, k2, p1, p2]
//       position_m: [3.7, 0.0, 0.6]    # camera centre in the vehicle frame
//       yaw_deg: 0.0                   # viewing direction, counter-clockwise from forward
//       pitch_down_deg: 30.0           # below the horizon
//       roll_deg: 0.0                  # about the viewing direction, clockwise seen from behind
//
// Reading is strict: unknown keys, missing keys, wrong types and non-finite
// numbers are IoErrors naming the file, the line and the key path.

#include <filesystem>
#include <string>

#include "parkslam/camera/camera_model.h"

namespace parkslam::io {

camera::CameraRig LoadRig(const std::filesystem::path& path);
camera::CameraRig RigFromYaml(const std::string& text, const std::string& source_name);
std::string RigToYaml(const camera::CameraRig& rig);

}  // namespace parkslam::io

#endif  // PARKSLAM_IO_RIG_YAML_H_
