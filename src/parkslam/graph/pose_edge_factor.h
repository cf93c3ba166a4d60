#ifndef PARKSLAM_GRAPH_POSE_EDGE_FACTOR_H_
#define PARKSLAM_GRAPH_POSE_EDGE_FACTOR_H_

// Relative-pose edge of a planar pose graph (g2o's EDGE_SE2).
//
// Blocks: pose_a = {x_a, y_a, yaw_a}, pose_b = {x_b, y_b, yaw_b} (T_world_pose).
// Measurement: Z = T_a_b = (t_z, yaw_z), information Omega over (x, y, yaw)
// in the frame of Z.
//
//   e = [ R(yaw_z)^T ( R(yaw_a)^T (t_b - t_a) - t_z ) ]     (= Z^-1 (A^-1 B)
//       [ wrap(yaw_b - yaw_a - yaw_z)                 ]        as a vector)
//   r = U e,   U^T U = Omega,   ||r||^2 = e^T Omega e
//
// RelativePoseError computes e alone (no weighting), for the plain factor
// here and for the Max-Mixture factor, which weights it per component.

#include <ceres/autodiff_cost_function.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "parkslam/common/se2.h"
#include "parkslam/mapping/costs/angle.h"

namespace parkslam::graph {

class RelativePoseError {
 public:
  explicit RelativePoseError(const SE2& T_a_b_measured)
      : t_z_(T_a_b_measured.translation()), yaw_z_rad_(T_a_b_measured.yaw()) {}

  template <typename T>
  bool operator()(const T* pose_a, const T* pose_b, T* error) const {
    using std::cos;
    using std::sin;
    const T dx = pose_b[0] - pose_a[0], dy = pose_b[1] - pose_a[1];
    const T ca = cos(pose_a[2]), sa = sin(pose_a[2]);
    // R(yaw_a)^T (t_b - t_a) - t_z
    const T qx = ca * dx + sa * dy - T(t_z_.x());
    const T qy = -sa * dx + ca * dy - T(t_z_.y());
    const double cz = std::cos(yaw_z_rad_), sz = std::sin(yaw_z_rad_);
    error[0] = cz * qx + sz * qy;
    error[1] = -sz * qx + cz * qy;
    error[2] = mapping::WrapAngle(pose_b[2] - pose_a[2] - T(yaw_z_rad_));
    return true;
  }

 private:
  Eigen::Vector2d t_z_;
  double yaw_z_rad_;
};

// Upper Cholesky factor U of an SPD information matrix: U^T U = Omega.
template <int N>
Eigen::Matrix<double, N, N> SqrtOfInformation(const Eigen::Matrix<double, N, N>& information) {
  return information.llt().matrixU();
}

class PoseEdgeFactor {
 public:
  PoseEdgeFactor(const SE2& T_a_b_measured, const Eigen::Matrix3d& information)
      : error_(T_a_b_measured), sqrt_information_(SqrtOfInformation<3>(information)) {}

  template <typename T>
  bool operator()(const T* pose_a, const T* pose_b, T* residuals) const {
    Eigen::Matrix<T, 3, 1> e;
    error_(pose_a, pose_b, e.data());
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residuals);
    r = sqrt_information_.cast<T>() * e;
    return true;
  }

  // The information must be symmetric positive definite (CheckPoseGraph).
  static ceres::CostFunction* Create(const SE2& T_a_b_measured,
                                     const Eigen::Matrix3d& information) {
    return new ceres::AutoDiffCostFunction<PoseEdgeFactor, 3, 3, 3>(
        new PoseEdgeFactor(T_a_b_measured, information));
  }

 private:
  RelativePoseError error_;
  Eigen::Matrix3d sqrt_information_;
};

}  // namespace parkslam::graph

#endif  // PARKSLAM_GRAPH_POSE_EDGE_FACTOR_H_
