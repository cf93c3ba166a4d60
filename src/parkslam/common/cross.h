#ifndef PARKSLAM_COMMON_CROSS_H_
#define PARKSLAM_COMMON_CROSS_H_

#include <Eigen/Core>

namespace parkslam {

// The z component of the 3D cross product of two plane vectors:
// a.x b.y - a.y b.x, positive when b lies counter-clockwise of a.
inline double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

}  // namespace parkslam

#endif  // PARKSLAM_COMMON_CROSS_H_
