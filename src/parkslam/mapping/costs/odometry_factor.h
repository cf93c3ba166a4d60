#ifndef PARKSLAM_MAPPING_COSTS_ODOMETRY_FACTOR_H_
#define PARKSLAM_MAPPING_COSTS_ODOMETRY_FACTOR_H_

// Relative-pose (odometry) factor between two vehicle poses; the paper's
// back-end graph (section III-C, "Optimization Framework"), with the Kalman
// dead-reckoning increment as the measurement.
//
// Blocks: pose_a = {x_a, y_a, yaw_a}, pose_b = {x_b, y_b, yaw_b} (T_map_vehicle).
// Measurement: T_a_b = (t_ab, yaw_ab) with 3x3 covariance Sigma (x, y, yaw).
//
//   e = [ R(yaw_a)^T (t_b - t_a) - t_ab         ]
//       [ wrap(yaw_b - yaw_a - yaw_ab)          ]
//   r = U e,   U = (Sigma^-1).llt().matrixU(),   ||r||^2 = e^T Sigma^-1 e

#include <ceres/autodiff_cost_function.h>

#include <Eigen/Core>

#include "parkslam/common/se2.h"
#include "parkslam/mapping/costs/angle.h"
#include "parkslam/mapping/costs/cost_util.h"

namespace parkslam::mapping {

class OdometryFactor {
 public:
  static constexpr int kNumResiduals = 3;

  OdometryFactor(const SE2& T_a_b_measured, const Eigen::Matrix3d& covariance)
      : t_ab_m_(T_a_b_measured.translation()),
        yaw_ab_rad_(T_a_b_measured.yaw()),
        sqrt_information_(SqrtInformation<3>(covariance)) {}

  template <typename T>
  bool operator()(const T* pose_a, const T* pose_b, T* residuals) const {
    const Eigen::Matrix<T, 2, 1> t_b_minus_t_a(pose_b[0] - pose_a[0], pose_b[1] - pose_a[1]);
    Eigen::Matrix<T, 3, 1> error;
    error.template head<2>() = RotateMapToBody(pose_a[2], t_b_minus_t_a) - t_ab_m_.cast<T>();
    error(2) = WrapAngle(pose_b[2] - pose_a[2] - T(yaw_ab_rad_));
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residuals);
    r = sqrt_information_.cast<T>() * error;
    return true;
  }

  // Throws std::invalid_argument for a covariance that is not SPD.
  static ceres::CostFunction* Create(const SE2& T_a_b_measured, const Eigen::Matrix3d& covariance) {
    return new ceres::AutoDiffCostFunction<OdometryFactor, kNumResiduals, 3, 3>(
        new OdometryFactor(T_a_b_measured, covariance));
  }

 private:
  Eigen::Vector2d t_ab_m_;
  double yaw_ab_rad_;
  Eigen::Matrix3d sqrt_information_;
};

}  // namespace parkslam::mapping

#endif  // PARKSLAM_MAPPING_COSTS_ODOMETRY_FACTOR_H_
