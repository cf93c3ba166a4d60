#ifndef PARKSLAM_MAPPING_COSTS_CORNER_OBSERVATION_FACTOR_H_
#define PARKSLAM_MAPPING_COSTS_CORNER_OBSERVATION_FACTOR_H_

// Observation of one parking-slot corner (a landmark point, section III-A)
// from a vehicle pose; a landmark edge of the back-end graph (section III-C).
//
// Blocks: pose = {x, y, yaw} (T_map_vehicle), corner = c = {x, y} (map frame).
// Measurement: z, the corner in the vehicle frame, with 2x2 covariance Sigma.
//
//   e = R(yaw)^T (c - t) - z
//   r = U e,   U = (Sigma^-1).llt().matrixU(),   ||r||^2 = e^T Sigma^-1 e

#include <ceres/autodiff_cost_function.h>

#include <Eigen/Core>

#include "parkslam/mapping/costs/cost_util.h"

namespace parkslam::mapping {

class CornerObservationFactor {
 public:
  static constexpr int kNumResiduals = 2;

  CornerObservationFactor(const Eigen::Vector2d& z_vehicle, const Eigen::Matrix2d& covariance)
      : z_vehicle_m_(z_vehicle), sqrt_information_(SqrtInformation<2>(covariance)) {}

  template <typename T>
  bool operator()(const T* pose, const T* corner, T* residuals) const {
    const Eigen::Matrix<T, 2, 1> c_minus_t(corner[0] - pose[0], corner[1] - pose[1]);
    const Eigen::Matrix<T, 2, 1> error =
        RotateMapToBody(pose[2], c_minus_t) - z_vehicle_m_.cast<T>();
    Eigen::Map<Eigen::Matrix<T, 2, 1>> r(residuals);
    r = sqrt_information_.cast<T>() * error;
    return true;
  }

  // Throws std::invalid_argument for a covariance that is not SPD.
  static ceres::CostFunction* Create(const Eigen::Vector2d& z_vehicle,
                                     const Eigen::Matrix2d& covariance) {
    return new ceres::AutoDiffCostFunction<CornerObservationFactor, kNumResiduals, 3, 2>(
        new CornerObservationFactor(z_vehicle, covariance));
  }

 private:
  Eigen::Vector2d z_vehicle_m_;
  Eigen::Matrix2d sqrt_information_;
};

}  // namespace parkslam::mapping

#endif  // PARKSLAM_MAPPING_COSTS_CORNER_OBSERVATION_FACTOR_H_
