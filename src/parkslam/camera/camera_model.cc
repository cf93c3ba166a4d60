#include "parkslam/camera/camera_model.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace parkslam::camera {
namespace {

// Kannala-Brandt: theta_d = theta (1 + k1 t^2 + k2 t^4 + k3 t^6 + k4 t^8).
double DistortTheta(double theta, const std::array<double, 4>& k) {
  const double t2 = theta * theta;
  return theta * (1.0 + t2 * (k[0] + t2 * (k[1] + t2 * (k[2] + t2 * k[3]))));
}

double DistortThetaDerivative(double theta, const std::array<double, 4>& k) {
  const double t2 = theta * theta;
  return 1.0 + t2 * (3.0 * k[0] + t2 * (5.0 * k[1] + t2 * (7.0 * k[2] + t2 * 9.0 * k[3])));
}

// The largest theta (up to pi) over which theta_d keeps growing: the
// model's valid field of view.
double MaxTheta(const std::array<double, 4>& k) {
  constexpr int kSteps = 2000;
  for (int i = 1; i <= kSteps; ++i) {
    const double theta = std::numbers::pi * i / kSteps;
    if (DistortThetaDerivative(theta, k) <= 0.0) return std::numbers::pi * (i - 1) / kSteps;
  }
  return std::numbers::pi;
}

}  // namespace

CameraModel::CameraModel(const CameraIntrinsics& intrinsics) : intrinsics_(intrinsics) {
  if (intrinsics_.kind == CameraKind::kFisheye) {
    max_theta_ = MaxTheta(intrinsics_.distortion);
    max_theta_d_ = DistortTheta(max_theta_, intrinsics_.distortion);
  }
}

std::optional<Eigen::Vector2d> CameraModel::Project(const Eigen::Vector3d& p,
                                                    bool require_inside) const {
  const CameraIntrinsics& in = intrinsics_;
  Eigen::Vector2d normalized;
  if (in.kind == CameraKind::kFisheye) {
    const double r = std::hypot(p.x(), p.y());
    const double theta = std::atan2(r, p.z());
    if (theta > max_theta_) return std::nullopt;
    const double theta_d = DistortTheta(theta, in.distortion);
    normalized = r > 1e-12 ? Eigen::Vector2d(p.x() / r * theta_d, p.y() / r * theta_d)
                           : Eigen::Vector2d::Zero();
  } else {
    if (p.z() <= 1e-9) return std::nullopt;
    const double x = p.x() / p.z(), y = p.y() / p.z();
    const auto& d = in.distortion;  // k1, k2, p1, p2
    const double r2 = x * x + y * y;
    const double radial = 1.0 + r2 * (d[0] + r2 * d[1]);
    normalized = {x * radial + 2 * d[2] * x * y + d[3] * (r2 + 2 * x * x),
                  y * radial + d[2] * (r2 + 2 * y * y) + 2 * d[3] * x * y};
  }
  const Eigen::Vector2d pixel(in.fx * normalized.x() + in.cx, in.fy * normalized.y() + in.cy);
  if (require_inside && (pixel.x() < -0.5 || pixel.y() < -0.5 || pixel.x() > in.width - 0.5 ||
                         pixel.y() > in.height - 0.5)) {
    return std::nullopt;
  }
  return pixel;
}

std::optional<Eigen::Vector3d> CameraModel::Unproject(const Eigen::Vector2d& pixel) const {
  const CameraIntrinsics& in = intrinsics_;
  const Eigen::Vector2d d((pixel.x() - in.cx) / in.fx, (pixel.y() - in.cy) / in.fy);
  if (in.kind == CameraKind::kFisheye) {
    const double theta_d = d.norm();
    if (theta_d < 1e-12) return Eigen::Vector3d(0, 0, 1);
    // Newton on theta_d = f(theta), within the monotonic range.
    const double max_theta = max_theta_;
    if (theta_d > max_theta_d_) return std::nullopt;
    double theta = std::min(theta_d, max_theta);
    for (int i = 0; i < 20; ++i) {
      const double step = (DistortTheta(theta, in.distortion) - theta_d) /
                          DistortThetaDerivative(theta, in.distortion);
      theta = std::clamp(theta - step, 0.0, max_theta);
      if (std::abs(step) < 1e-12) break;
    }
    const Eigen::Vector2d dir = d / theta_d;
    return Eigen::Vector3d(std::sin(theta) * dir.x(), std::sin(theta) * dir.y(), std::cos(theta));
  }
  // Pinhole: undistort by fixed-point iteration (as OpenCV's undistortPoints).
  const auto& k = in.distortion;
  Eigen::Vector2d u = d;
  for (int i = 0; i < 20; ++i) {
    const double r2 = u.squaredNorm();
    const double radial = 1.0 + r2 * (k[0] + r2 * k[1]);
    const Eigen::Vector2d tangential(2 * k[2] * u.x() * u.y() + k[3] * (r2 + 2 * u.x() * u.x()),
                                     k[2] * (r2 + 2 * u.y() * u.y()) + 2 * k[3] * u.x() * u.y());
    u = (d - tangential) / radial;
  }
  return Eigen::Vector3d(u.x(), u.y(), 1.0).normalized();
}

const CameraConfig* CameraRig::Find(const std::string& name) const {
  for (const CameraConfig& c : cameras) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

namespace {

// A camera looking along `yaw` (in the vehicle's x-y plane, counter-
// clockwise from forward) and `pitch_down` below the horizon: camera z
// along the viewing direction, camera x to its right, camera y down.
Eigen::Isometry3d MountedCamera(const Eigen::Vector3d& position, double yaw, double pitch_down) {
  const Eigen::Vector3d forward(std::cos(yaw) * std::cos(pitch_down),
                                std::sin(yaw) * std::cos(pitch_down), -std::sin(pitch_down));
  const Eigen::Vector3d right(std::sin(yaw), -std::cos(yaw), 0.0);
  const Eigen::Vector3d down = forward.cross(right);
  Eigen::Matrix3d R;  // columns: camera axes in the vehicle frame
  R.col(0) = right;
  R.col(1) = down;
  R.col(2) = forward;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = position;
  return T;
}

CameraConfig Fisheye(const std::string& name, const Eigen::Vector3d& position, double yaw,
                     double pitch_down) {
  CameraConfig c;
  c.name = name;
  c.intrinsics.kind = CameraKind::kFisheye;
  c.intrinsics.width = 640;
  c.intrinsics.height = 480;
  c.intrinsics.fx = c.intrinsics.fy = 180.0;
  c.intrinsics.cx = 319.5;
  c.intrinsics.cy = 239.5;
  c.intrinsics.distortion = {0.02, -0.005, 0.001, -0.0002};
  c.T_vehicle_camera = MountedCamera(position, yaw, pitch_down);
  return c;
}

}  // namespace

CameraRig DefaultRig() {
  constexpr double kDeg = std::numbers::pi / 180.0;
  CameraRig rig;
  rig.cameras.push_back(Fisheye("front", {3.7, 0.0, 0.6}, 0.0, 30 * kDeg));
  rig.cameras.push_back(Fisheye("rear", {-1.0, 0.0, 0.8}, 180 * kDeg, 30 * kDeg));
  rig.cameras.push_back(Fisheye("left", {2.0, 1.0, 1.0}, 90 * kDeg, 60 * kDeg));
  rig.cameras.push_back(Fisheye("right", {2.0, -1.0, 1.0}, -90 * kDeg, 60 * kDeg));
  CameraConfig mono;
  mono.name = "front_mono";
  mono.intrinsics.kind = CameraKind::kPinhole;
  mono.intrinsics.width = 1280;
  mono.intrinsics.height = 720;
  mono.intrinsics.fx = mono.intrinsics.fy = 640.0;
  mono.intrinsics.cx = 639.5;
  mono.intrinsics.cy = 359.5;
  mono.T_vehicle_camera = MountedCamera({1.8, 0.3, 1.3}, 0.0, 0.0);
  rig.cameras.push_back(mono);
  return rig;
}

CameraRig WithFisheyeResolution(const CameraRig& rig, double scale) {
  if (!(scale >= 0.25 && scale <= 4.0)) {
    throw std::invalid_argument("fisheye resolution scale must be in [0.25, 4], got " +
                                std::to_string(scale));
  }
  CameraRig out = rig;
  for (CameraConfig& c : out.cameras) {
    if (c.intrinsics.kind != CameraKind::kFisheye) continue;
    CameraIntrinsics& k = c.intrinsics;
    k.width = static_cast<int>(std::lround(k.width * scale));
    k.height = static_cast<int>(std::lround(k.height * scale));
    k.fx *= scale;
    k.fy *= scale;
    // Pixel centres at integers: the image's edge (-0.5) stays its edge.
    k.cx = (k.cx + 0.5) * scale - 0.5;
    k.cy = (k.cy + 0.5) * scale - 0.5;
  }
  return out;
}

}  // namespace parkslam::camera
