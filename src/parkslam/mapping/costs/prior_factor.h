#ifndef PARKSLAM_MAPPING_COSTS_PRIOR_FACTOR_H_
#define PARKSLAM_MAPPING_COSTS_PRIOR_FACTOR_H_

// Unary priors of the back-end graph (section III-C): a pose prior (anchors
// the gauge, e.g. the first pose) and a weak point prior that keeps a corner
// landmark connected when every observation of it picks the null component of
// a max-mixture (DESIGN.md section 5).
//
// PosePriorFactor, block pose = {x, y, yaw}, prior (t_p, yaw_p), covariance Sigma:
//   e = [ t - t_p ; wrap(yaw - yaw_p) ],  r = U e,  U = (Sigma^-1).llt().matrixU()
//
// PointPriorFactor, block corner = c = {x, y}, prior p, std sigma (isotropic):
//   r = (c - p) / sigma
//
// ScalarPriorFactor, block v = {v}, prior p, std sigma (the wheel speed's
// scale error of OdometryFactor, whose prior is the spread of real cars'):
//   r = (v - p) / sigma

#include <ceres/autodiff_cost_function.h>

#include <Eigen/Core>

#include "parkslam/common/se2.h"
#include "parkslam/mapping/costs/angle.h"
#include "parkslam/mapping/costs/cost_util.h"

namespace parkslam::mapping {

class PosePriorFactor {
 public:
  static constexpr int kNumResiduals = 3;

  PosePriorFactor(const SE2& prior, const Eigen::Matrix3d& covariance)
      : t_prior_m_(prior.translation()),
        yaw_prior_rad_(prior.yaw()),
        sqrt_information_(SqrtInformation<3>(covariance)) {}

  template <typename T>
  bool operator()(const T* pose, T* residuals) const {
    Eigen::Matrix<T, 3, 1> error;
    error(0) = pose[0] - T(t_prior_m_.x());
    error(1) = pose[1] - T(t_prior_m_.y());
    error(2) = WrapAngle(pose[2] - T(yaw_prior_rad_));
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residuals);
    r = sqrt_information_.cast<T>() * error;
    return true;
  }

  // Throws std::invalid_argument for a covariance that is not SPD.
  static ceres::CostFunction* Create(const SE2& prior, const Eigen::Matrix3d& covariance) {
    return new ceres::AutoDiffCostFunction<PosePriorFactor, kNumResiduals, 3>(
        new PosePriorFactor(prior, covariance));
  }

 private:
  Eigen::Vector2d t_prior_m_;
  double yaw_prior_rad_;
  Eigen::Matrix3d sqrt_information_;
};

class PointPriorFactor {
 public:
  static constexpr int kNumResiduals = 2;

  // Throws std::invalid_argument unless sigma_m > 0.
  PointPriorFactor(const Eigen::Vector2d& prior_map, double sigma_m)
      : prior_map_m_(prior_map), inverse_sigma_(1.0 / CheckedSigma(sigma_m, "sigma_m")) {}

  template <typename T>
  bool operator()(const T* corner, T* residuals) const {
    residuals[0] = (corner[0] - T(prior_map_m_.x())) * inverse_sigma_;
    residuals[1] = (corner[1] - T(prior_map_m_.y())) * inverse_sigma_;
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector2d& prior_map, double sigma_m) {
    return new ceres::AutoDiffCostFunction<PointPriorFactor, kNumResiduals, 2>(
        new PointPriorFactor(prior_map, sigma_m));
  }

 private:
  Eigen::Vector2d prior_map_m_;
  double inverse_sigma_;
};

class ScalarPriorFactor {
 public:
  static constexpr int kNumResiduals = 1;

  // Throws std::invalid_argument unless sigma > 0.
  ScalarPriorFactor(double prior, double sigma)
      : prior_(prior), inverse_sigma_(1.0 / CheckedSigma(sigma, "sigma")) {}

  template <typename T>
  bool operator()(const T* value, T* residuals) const {
    residuals[0] = (value[0] - T(prior_)) * inverse_sigma_;
    return true;
  }

  static ceres::CostFunction* Create(double prior, double sigma) {
    return new ceres::AutoDiffCostFunction<ScalarPriorFactor, kNumResiduals, 1>(
        new ScalarPriorFactor(prior, sigma));
  }

 private:
  double prior_;
  double inverse_sigma_;
};

}  // namespace parkslam::mapping

#endif  // PARKSLAM_MAPPING_COSTS_PRIOR_FACTOR_H_
