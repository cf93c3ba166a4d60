#ifndef PARKSLAM_MAPPING_COSTS_TAG_OBSERVATION_FACTOR_H_
#define PARKSLAM_MAPPING_COSTS_TAG_OBSERVATION_FACTOR_H_

// Observation of an AprilTag (section III-B: position x = sin(alpha) d,
// y = cos(alpha) d in the vehicle frame, orientation from PnP) from a vehicle
// pose; a landmark edge of the back-end graph (section III-C).
//
// Blocks: pose = {x, y, yaw} (T_map_vehicle),
//         tag = {p_x, p_y, yaw_tag} (map frame; yaw_tag = outward normal).
// Measurement: z (tag position in the vehicle frame) with 2x2 covariance
// Sigma_p, z_yaw (tag normal in the vehicle frame) with std sigma_yaw.
//
//   e = [ R(yaw)^T (p_tag - t) - z    ]
//       [ wrap(yaw_tag - yaw - z_yaw) ]
//   Sigma = blockdiag(Sigma_p, sigma_yaw^2)
//   r = U e,   U = (Sigma^-1).llt().matrixU() = blockdiag(U_p, 1 / sigma_yaw)

#include <ceres/autodiff_cost_function.h>

#include <Eigen/Core>

#include "parkslam/mapping/costs/angle.h"
#include "parkslam/mapping/costs/cost_util.h"

namespace parkslam::mapping {

class TagObservationFactor {
 public:
  static constexpr int kNumResiduals = 3;

  // Throws std::invalid_argument for a covariance that is not SPD or a
  // yaw_sigma_rad that is not > 0.
  TagObservationFactor(const Eigen::Vector2d& z_vehicle, double yaw_vehicle,
                       const Eigen::Matrix2d& position_covariance, double yaw_sigma_rad)
      : z_vehicle_m_(z_vehicle),
        z_yaw_rad_(WrapAngle(yaw_vehicle)),
        sqrt_information_(SqrtInformation<3>(
            BlockDiagonal(position_covariance, CheckedSigma(yaw_sigma_rad, "yaw_sigma_rad")))) {}

  template <typename T>
  bool operator()(const T* pose, const T* tag, T* residuals) const {
    const Eigen::Matrix<T, 2, 1> p_minus_t(tag[0] - pose[0], tag[1] - pose[1]);
    Eigen::Matrix<T, 3, 1> error;
    error.template head<2>() = RotateMapToBody(pose[2], p_minus_t) - z_vehicle_m_.cast<T>();
    error(2) = WrapAngle(tag[2] - pose[2] - T(z_yaw_rad_));
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residuals);
    r = sqrt_information_.cast<T>() * error;
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector2d& z_vehicle, double yaw_vehicle,
                                     const Eigen::Matrix2d& position_covariance,
                                     double yaw_sigma_rad) {
    return new ceres::AutoDiffCostFunction<TagObservationFactor, kNumResiduals, 3, 3>(
        new TagObservationFactor(z_vehicle, yaw_vehicle, position_covariance, yaw_sigma_rad));
  }

 private:
  static Eigen::Matrix3d BlockDiagonal(const Eigen::Matrix2d& position_covariance,
                                       double yaw_sigma_rad) {
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    covariance.topLeftCorner<2, 2>() = position_covariance;
    covariance(2, 2) = yaw_sigma_rad * yaw_sigma_rad;
    return covariance;
  }

  Eigen::Vector2d z_vehicle_m_;
  double z_yaw_rad_;
  Eigen::Matrix3d sqrt_information_;
};

}  // namespace parkslam::mapping

#endif  // PARKSLAM_MAPPING_COSTS_TAG_OBSERVATION_FACTOR_H_
