#include "parkslam/mapping/costs/max_mixture_corner_factor.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "parkslam/mapping/costs/cost_util.h"

namespace parkslam::mapping {
namespace {

constexpr int kPoseSize = 3;
constexpr int kCornerSize = 2;

}  // namespace

MaxMixtureCornerFactor::MaxMixtureCornerFactor(std::vector<CornerMeasurement> measurements,
                                               std::vector<double> candidate_weights,
                                               double null_weight, double null_chi2) {
  if (measurements.empty()) {
    throw std::invalid_argument("MaxMixtureCornerFactor: no measurements");
  }
  if (candidate_weights.empty()) {
    throw std::invalid_argument("MaxMixtureCornerFactor: no candidates");
  }
  for (const double w : candidate_weights) {
    if (!(std::isfinite(w) && w > 0.0)) {
      throw std::invalid_argument(
          "MaxMixtureCornerFactor: candidate weights must be finite and > 0");
    }
  }
  if (!(std::isfinite(null_weight) && null_weight >= 0.0)) {
    throw std::invalid_argument("MaxMixtureCornerFactor: null_weight must be finite and >= 0");
  }
  if (!(std::isfinite(null_chi2) && null_chi2 >= 0.0)) {
    throw std::invalid_argument("MaxMixtureCornerFactor: null_chi2 must be finite and >= 0");
  }

  z_vehicle_m_.reserve(measurements.size());
  sqrt_information_.reserve(measurements.size());
  for (const CornerMeasurement& m : measurements) {
    z_vehicle_m_.push_back(m.z_vehicle);
    sqrt_information_.push_back(SqrtInformation<2>(m.covariance));
  }

  min_normalization_ = std::numeric_limits<double>::infinity();
  negative_log_weights_.reserve(candidate_weights.size());
  for (const double w : candidate_weights) {
    negative_log_weights_.push_back(-std::log(w));
    min_normalization_ = std::min(min_normalization_, -std::log(w));
  }
  has_null_ = null_weight > 0.0;
  if (has_null_) {
    null_cost_ = -std::log(null_weight) + 0.5 * null_chi2;
    min_normalization_ = std::min(min_normalization_, null_cost_);
  }

  const int num_blocks = 1 + num_candidates() * num_measurements();
  set_num_residuals(2 * num_measurements() + 1);
  std::vector<int>* sizes = mutable_parameter_block_sizes();
  sizes->assign(static_cast<std::size_t>(num_blocks), kCornerSize);
  (*sizes)[0] = kPoseSize;
}

MaxMixtureCornerFactor* MaxMixtureCornerFactor::Create(std::vector<CornerMeasurement> measurements,
                                                       std::vector<double> candidate_weights,
                                                       double null_weight, double null_chi2) {
  return new MaxMixtureCornerFactor(std::move(measurements), std::move(candidate_weights),
                                    null_weight, null_chi2);
}

double MaxMixtureCornerFactor::CandidateAcceptanceChi2(double candidate_weight, double null_weight,
                                                       double null_chi2) {
  return null_chi2 + 2.0 * std::log(candidate_weight / null_weight);
}

Eigen::Vector2d MaxMixtureCornerFactor::WhitenedError(const double* pose, const double* corner,
                                                      int measurement) const {
  const Eigen::Vector2d c_minus_t(corner[0] - pose[0], corner[1] - pose[1]);
  const std::size_t j = static_cast<std::size_t>(measurement);
  return sqrt_information_[j] * (RotateMapToBody(pose[2], c_minus_t) - z_vehicle_m_[j]);
}

double MaxMixtureCornerFactor::CandidateChi2(double const* const* parameters, int candidate) const {
  double chi2 = 0.0;
  for (int j = 0; j < num_measurements(); ++j) {
    chi2 +=
        WhitenedError(parameters[0], parameters[CornerBlockIndex(candidate, j)], j).squaredNorm();
  }
  return chi2;
}

double MaxMixtureCornerFactor::ComponentCost(double const* const* parameters, int component) const {
  if (component == kNullComponent) {
    return has_null_ ? null_cost_ : std::numeric_limits<double>::infinity();
  }
  return negative_log_weights_[static_cast<std::size_t>(component)] +
         0.5 * CandidateChi2(parameters, component);
}

int MaxMixtureCornerFactor::Choose(double const* const* parameters) const {
  int best = kNullComponent;
  double best_cost = ComponentCost(parameters, kNullComponent);  // inf if none
  for (int k = 0; k < num_candidates(); ++k) {
    const double cost = ComponentCost(parameters, k);
    // Strict: the null and earlier candidates keep ties. The first candidate
    // is always taken over an absent null (inf), even if its cost is inf/NaN.
    if (cost < best_cost || (best == kNullComponent && !has_null_)) {
      best = k;
      best_cost = cost;
    }
  }
  return best;
}

int MaxMixtureCornerFactor::ChosenComponent(double const* const* parameters) const {
  return Choose(parameters);
}

bool MaxMixtureCornerFactor::Evaluate(double const* const* parameters, double* residuals,
                                      double** jacobians) const {
  const int num_j = num_measurements();
  const int num_r = num_residuals();
  const int chosen = Choose(parameters);
  const double* pose = parameters[0];

  // The normalization entry: N_chosen - N_min >= 0 by construction of N_min.
  const double n_chosen = chosen == kNullComponent
                              ? null_cost_
                              : negative_log_weights_[static_cast<std::size_t>(chosen)];
  residuals[num_r - 1] = std::sqrt(2.0 * std::max(0.0, n_chosen - min_normalization_));

  if (chosen == kNullComponent) {
    std::fill(residuals, residuals + 2 * num_j, 0.0);
  } else {
    for (int j = 0; j < num_j; ++j) {
      const Eigen::Vector2d e = WhitenedError(pose, parameters[CornerBlockIndex(chosen, j)], j);
      residuals[2 * j] = e.x();
      residuals[2 * j + 1] = e.y();
    }
  }

  if (jacobians == nullptr) return true;

  const std::vector<int>& sizes = parameter_block_sizes();
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    if (jacobians[i] != nullptr) {
      std::fill(jacobians[i], jacobians[i] + num_r * sizes[i], 0.0);
    }
  }
  if (chosen == kNullComponent) return true;

  const double c = std::cos(pose[2]);
  const double s = std::sin(pose[2]);
  Eigen::Matrix2d rotation_transpose;  // R(yaw)^T
  rotation_transpose << c, s, -s, c;

  using RowMajor2x3 = Eigen::Matrix<double, 2, 3, Eigen::RowMajor>;
  using RowMajor2x2 = Eigen::Matrix<double, 2, 2, Eigen::RowMajor>;
  for (int j = 0; j < num_j; ++j) {
    const std::size_t jj = static_cast<std::size_t>(j);
    const Eigen::Matrix2d& sqrt_info = sqrt_information_[jj];
    const int corner_block = CornerBlockIndex(chosen, j);
    if (jacobians[0] != nullptr) {
      const double* corner = parameters[corner_block];
      const Eigen::Vector2d q =
          rotation_transpose * Eigen::Vector2d(corner[0] - pose[0], corner[1] - pose[1]);
      Eigen::Matrix<double, 2, 3> d_error_d_pose;
      d_error_d_pose.leftCols<2>() = -rotation_transpose;
      d_error_d_pose.col(2) = Eigen::Vector2d(q.y(), -q.x());
      Eigen::Map<RowMajor2x3>(jacobians[0] + 2 * j * kPoseSize) = sqrt_info * d_error_d_pose;
    }
    if (jacobians[corner_block] != nullptr) {
      Eigen::Map<RowMajor2x2>(jacobians[corner_block] + 2 * j * kCornerSize) =
          sqrt_info * rotation_transpose;
    }
  }
  return true;
}

}  // namespace parkslam::mapping
