#ifndef PARKSLAM_MAPPING_COSTS_ODOMETRY_FACTOR_H_
#define PARKSLAM_MAPPING_COSTS_ODOMETRY_FACTOR_H_

// Relative-pose (odometry) factor between two vehicle poses; the paper's
// back-end graph (section III-C, "Optimization Framework"), with the Kalman
// dead-reckoning increment as the measurement.
//
// Blocks: pose_a = {x_a, y_a, yaw_a}, pose_b = {x_b, y_b, yaw_b} (T_map_vehicle),
// scale = {s}: the wheel speed's scale error, one block that every odometry
// factor of the graph shares.
// Measurement: T_a_b = (t_ab, yaw_ab) with 3x3 covariance Sigma (x, y, yaw),
// integrated by the dead reckoning with its own estimate s_o of that error.
//
// The wheel reads (1 + s) times the speed, so the car moved
// (1 + s_o) / (1 + s) t_ab ~ (1 - (s - s_o)) t_ab. The error is the same
// fraction in every increment of a drive: as white noise per factor it
// would average away along the drive, and the graph would state far less
// drift between loop closures than the drive has.
//
//   e = [ R(yaw_a)^T (t_b - t_a) - (1 - (s - s_o)) t_ab ]
//       [ wrap(yaw_b - yaw_a - yaw_ab)                  ]
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

  OdometryFactor(const SE2& T_a_b_measured, const Eigen::Matrix3d& covariance,
                 double odometry_wheel_scale)
      : t_ab_m_(T_a_b_measured.translation()),
        yaw_ab_rad_(T_a_b_measured.yaw()),
        odometry_wheel_scale_(odometry_wheel_scale),
        sqrt_information_(SqrtInformation<3>(covariance)) {}

  template <typename T>
  bool operator()(const T* pose_a, const T* pose_b, const T* scale, T* residuals) const {
    const Eigen::Matrix<T, 2, 1> t_b_minus_t_a(pose_b[0] - pose_a[0], pose_b[1] - pose_a[1]);
    const T distance_factor = T(1.0) - (scale[0] - T(odometry_wheel_scale_));
    Eigen::Matrix<T, 3, 1> error;
    error.template head<2>() =
        RotateMapToBody(pose_a[2], t_b_minus_t_a) - distance_factor * t_ab_m_.cast<T>();
    error(2) = WrapAngle(pose_b[2] - pose_a[2] - T(yaw_ab_rad_));
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residuals);
    r = sqrt_information_.cast<T>() * error;
    return true;
  }

  // Throws std::invalid_argument for a covariance that is not SPD.
  static ceres::CostFunction* Create(const SE2& T_a_b_measured, const Eigen::Matrix3d& covariance,
                                     double odometry_wheel_scale = 0.0) {
    return new ceres::AutoDiffCostFunction<OdometryFactor, kNumResiduals, 3, 3, 1>(
        new OdometryFactor(T_a_b_measured, covariance, odometry_wheel_scale));
  }

 private:
  Eigen::Vector2d t_ab_m_;
  double yaw_ab_rad_;
  double odometry_wheel_scale_;
  Eigen::Matrix3d sqrt_information_;
};

}  // namespace parkslam::mapping

#endif  // PARKSLAM_MAPPING_COSTS_ODOMETRY_FACTOR_H_
