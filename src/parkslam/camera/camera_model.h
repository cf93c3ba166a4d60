#ifndef PARKSLAM_CAMERA_CAMERA_MODEL_H_
#define PARKSLAM_CAMERA_CAMERA_MODEL_H_

// Camera models and the camera rig (paper section III, Fig. 2: four fisheye
// cameras on the bumpers and mirrors, fused into a top view; a monocular
// front camera for AprilTags). Camera frame: OpenCV convention, x right,
// y down, z forward. Pixel coordinates: 0-based, (0, 0) the centre of the
// top-left pixel.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace parkslam::camera {

enum class CameraKind { kPinhole, kFisheye };

struct CameraIntrinsics {
  CameraKind kind = CameraKind::kPinhole;
  int width = 640, height = 480;
  double fx = 300.0, fy = 300.0, cx = 319.5, cy = 239.5;
  // Fisheye: Kannala-Brandt k1..k4 as OpenCV's cv::fisheye
  //   theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8).
  // Pinhole: radial-tangential k1, k2, p1, p2 (OpenCV's first four).
  std::array<double, 4> distortion{0.0, 0.0, 0.0, 0.0};
};

// A camera's pose on the vehicle: T_vehicle_camera maps camera coordinates
// into the vehicle frame (x forward, y left, z up, origin at the rear axle
// on the ground).
struct CameraConfig {
  std::string name;
  CameraIntrinsics intrinsics;
  Eigen::Isometry3d T_vehicle_camera = Eigen::Isometry3d::Identity();
};

class CameraModel {
 public:
  explicit CameraModel(const CameraIntrinsics& intrinsics);

  const CameraIntrinsics& intrinsics() const { return intrinsics_; }
  int width() const { return intrinsics_.width; }
  int height() const { return intrinsics_.height; }

  // The pixel of a point in the camera frame; empty behind the camera (or
  // beyond the fisheye's valid field of view) and outside the image when
  // require_inside.
  std::optional<Eigen::Vector2d> Project(const Eigen::Vector3d& p_camera,
                                         bool require_inside = true) const;
  // The unit ray of a pixel in the camera frame; empty where the model has
  // no inverse (outside the valid field of view).
  std::optional<Eigen::Vector3d> Unproject(const Eigen::Vector2d& pixel) const;

 private:
  CameraIntrinsics intrinsics_;
  // Fisheye: the largest angle from the axis over which the model is
  // monotonic, and its distorted radius.
  double max_theta_ = 0.0;
  double max_theta_d_ = 0.0;
};

// The cameras of a vehicle, by name.
struct CameraRig {
  std::vector<CameraConfig> cameras;
  const CameraConfig* Find(const std::string& name) const;
};

// The built-in rig of the simulator: fisheye cameras "front" (front
// bumper), "rear" (rear bumper), "left" and "right" (mirrors), 640x480 with
// about 190 degrees of view, looking down at the ground around the car; and
// the pinhole "front_mono" (1280x720, f = 640 px) left of the rear-view
// mirror, as in the paper.
CameraRig DefaultRig();

// The rig with its fisheyes' resolution scaled by `scale` (their field of
// view unchanged: focal lengths scaled, principal points kept at the same
// place of the image); other cameras as they were. Throws
// std::invalid_argument unless 0.25 <= scale <= 4.
CameraRig WithFisheyeResolution(const CameraRig& rig, double scale);

}  // namespace parkslam::camera

#endif  // PARKSLAM_CAMERA_CAMERA_MODEL_H_
