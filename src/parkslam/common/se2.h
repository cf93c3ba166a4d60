#ifndef PARKSLAM_COMMON_SE2_H_
#define PARKSLAM_COMMON_SE2_H_

#include <Eigen/Core>
#include <cmath>

#include "parkslam/common/angles.h"

namespace parkslam {

// A rigid transform in the plane. Named by the frames it maps between:
// T_a_b maps a point expressed in frame b into frame a (p_a = T_a_b * p_b),
// so T_map_vehicle is the pose of the vehicle in the map.
class SE2 {
 public:
  SE2() = default;
  SE2(double x_m, double y_m, double yaw_rad)
      : translation_(x_m, y_m), yaw_rad_(NormalizeAngle(yaw_rad)) {}
  SE2(const Eigen::Vector2d& translation, double yaw_rad)
      : translation_(translation), yaw_rad_(NormalizeAngle(yaw_rad)) {}

  const Eigen::Vector2d& translation() const { return translation_; }
  double x() const { return translation_.x(); }
  double y() const { return translation_.y(); }
  double yaw() const { return yaw_rad_; }

  Eigen::Matrix2d rotation() const {
    const double c = std::cos(yaw_rad_), s = std::sin(yaw_rad_);
    Eigen::Matrix2d r;
    r << c, -s, s, c;
    return r;
  }

  SE2 inverse() const {
    const Eigen::Matrix2d rt = rotation().transpose();
    return SE2(-(rt * translation_), -yaw_rad_);
  }

  SE2 operator*(const SE2& other) const {
    return SE2(translation_ + rotation() * other.translation_, yaw_rad_ + other.yaw_rad_);
  }

  Eigen::Vector2d operator*(const Eigen::Vector2d& p) const {
    return translation_ + rotation() * p;
  }

  // 3x3 homogeneous matrix.
  Eigen::Matrix3d matrix() const {
    Eigen::Matrix3d m = Eigen::Matrix3d::Identity();
    m.topLeftCorner<2, 2>() = rotation();
    m.topRightCorner<2, 1>() = translation_;
    return m;
  }

 private:
  Eigen::Vector2d translation_ = Eigen::Vector2d::Zero();
  double yaw_rad_ = 0.0;
};

// Interpolates between two poses: translation linearly, yaw along the shorter arc.
inline SE2 Interpolate(const SE2& a, const SE2& b, double fraction) {
  return SE2(a.translation() + fraction * (b.translation() - a.translation()),
             a.yaw() + fraction * AngleDiff(b.yaw(), a.yaw()));
}

}  // namespace parkslam

#endif  // PARKSLAM_COMMON_SE2_H_
