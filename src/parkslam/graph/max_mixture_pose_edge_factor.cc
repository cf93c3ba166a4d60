#include "parkslam/graph/max_mixture_pose_edge_factor.h"

#include <cmath>
#include <stdexcept>

namespace parkslam::graph {

MaxMixturePoseEdgeFactor::MaxMixturePoseEdgeFactor(const SE2& T_a_b_measured,
                                                   const Eigen::Matrix3d& information,
                                                   double null_weight,
                                                   double null_information_scale)
    : error_(new RelativePoseError(T_a_b_measured)),
      information_(information),
      sqrt_information_(SqrtOfInformation<3>(information)) {
  if (!(null_weight > 0.0 && null_weight <= 1.0)) {
    throw std::invalid_argument("MaxMixturePoseEdgeFactor: null_weight must be in (0, 1]");
  }
  if (!(null_information_scale > 0.0 && null_information_scale < 1.0)) {
    throw std::invalid_argument(
        "MaxMixturePoseEdgeFactor: null_information_scale must be in (0, 1)");
  }
  sqrt_null_scale_ = std::sqrt(null_information_scale);
  // N_0 - N_1 = -log w_0 - 0.5 log det(s Omega) + 0.5 log det(Omega)
  //           = -log w_0 - 1.5 log s  >= 0 for w_0 <= 1, s < 1.
  null_normalization_ =
      std::sqrt(2.0 * (-std::log(null_weight) - 1.5 * std::log(null_information_scale)));
  threshold_chi2_ = NullThresholdChi2(null_weight, null_information_scale);
}

double MaxMixturePoseEdgeFactor::NullThresholdChi2(double null_weight,
                                                   double null_information_scale) {
  return 2.0 * (-std::log(null_weight) - 1.5 * std::log(null_information_scale)) /
         (1.0 - null_information_scale);
}

bool MaxMixturePoseEdgeFactor::NullChosen(const double* pose_a, const double* pose_b) const {
  const double* parameters[2] = {pose_a, pose_b};
  Eigen::Vector3d e;
  if (!error_.Evaluate(parameters, e.data(), nullptr)) return false;
  // Strict: a tie keeps the edge.
  return e.dot(information_ * e) > threshold_chi2_;
}

bool MaxMixturePoseEdgeFactor::Evaluate(double const* const* parameters, double* residuals,
                                        double** jacobians) const {
  Eigen::Vector3d e;
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> de_da, de_db;
  double* error_jacobians[2] = {de_da.data(), de_db.data()};
  if (!error_.Evaluate(parameters, e.data(), jacobians != nullptr ? error_jacobians : nullptr)) {
    return false;
  }
  const bool null = e.dot(information_ * e) > threshold_chi2_;
  const double scale = null ? sqrt_null_scale_ : 1.0;
  Eigen::Map<Eigen::Vector4d> r(residuals);
  r.head<3>() = scale * (sqrt_information_ * e);
  // N_min = N_1 (the edge's own component), so the edge's entry is 0.
  r(3) = null ? null_normalization_ : 0.0;
  if (jacobians == nullptr) return true;
  const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>* de[2] = {&de_da, &de_db};
  for (int block = 0; block < 2; ++block) {
    if (jacobians[block] == nullptr) continue;
    Eigen::Map<Eigen::Matrix<double, 4, 3, Eigen::RowMajor>> J(jacobians[block]);
    J.topRows<3>() = scale * (sqrt_information_ * *de[block]);
    J.row(3).setZero();
  }
  return true;
}

}  // namespace parkslam::graph
