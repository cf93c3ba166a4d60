#ifndef PARKSLAM_GRAPH_POINT_EDGE_FACTOR_H_
#define PARKSLAM_GRAPH_POINT_EDGE_FACTOR_H_

// Pose-to-point edge of a planar graph (g2o's EDGE_SE2_XY): a landmark seen
// from a pose.
//
// Blocks: pose = {x, y, yaw} (T_world_pose), point = {x, y} (p_world).
// Measurement: z, the point in the pose's frame, information Omega (2 x 2).
//
//   e = R(yaw)^T (p - t) - z,   r = U e,   U^T U = Omega

#include <ceres/autodiff_cost_function.h>

#include <Eigen/Core>

#include "parkslam/graph/pose_edge_factor.h"

namespace parkslam::graph {

class PointEdgeFactor {
 public:
  PointEdgeFactor(const Eigen::Vector2d& p_pose_measured, const Eigen::Matrix2d& information)
      : z_(p_pose_measured), sqrt_information_(SqrtOfInformation<2>(information)) {}

  template <typename T>
  bool operator()(const T* pose, const T* point, T* residuals) const {
    using std::cos;
    using std::sin;
    const T dx = point[0] - pose[0], dy = point[1] - pose[1];
    const T c = cos(pose[2]), s = sin(pose[2]);
    Eigen::Matrix<T, 2, 1> e(c * dx + s * dy - T(z_.x()), -s * dx + c * dy - T(z_.y()));
    Eigen::Map<Eigen::Matrix<T, 2, 1>> r(residuals);
    r = sqrt_information_.cast<T>() * e;
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector2d& p_pose_measured,
                                     const Eigen::Matrix2d& information) {
    return new ceres::AutoDiffCostFunction<PointEdgeFactor, 2, 3, 2>(
        new PointEdgeFactor(p_pose_measured, information));
  }

 private:
  Eigen::Vector2d z_;
  Eigen::Matrix2d sqrt_information_;
};

}  // namespace parkslam::graph

#endif  // PARKSLAM_GRAPH_POINT_EDGE_FACTOR_H_
