#ifndef PARKSLAM_MAPPING_COSTS_COST_UTIL_H_
#define PARKSLAM_MAPPING_COSTS_COST_UTIL_H_

// Helpers shared by the cost functors.
//
// Whitening: for an error e with covariance Sigma, the information is
// Omega = Sigma^-1 and its Cholesky factorization Omega = L L^T = U^T U with
// U = L^T = Omega.llt().matrixU(). The residual r = U e then gives
//   ||r||^2 = e^T U^T U e = e^T Omega e,
// the Mahalanobis distance. (r = L e would give e^T L^T L e, which differs
// from e^T Omega e unless Omega is diagonal; DESIGN.md section 4.)

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <cmath>
#include <stdexcept>
#include <string>

namespace parkslam::mapping {

// Upper Cholesky factor U of the information covariance^-1 (U^T U = Sigma^-1).
// Throws std::invalid_argument unless the covariance is finite, symmetric and
// positive definite.
template <int N>
Eigen::Matrix<double, N, N> SqrtInformation(const Eigen::Matrix<double, N, N>& covariance) {
  if (!covariance.allFinite()) {
    throw std::invalid_argument("covariance has a non-finite entry");
  }
  const double scale = covariance.cwiseAbs().maxCoeff();
  if (!((covariance - covariance.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * scale)) {
    throw std::invalid_argument("covariance is not symmetric");
  }
  const Eigen::LLT<Eigen::Matrix<double, N, N>> covariance_llt(covariance);
  if (covariance_llt.info() != Eigen::Success) {
    throw std::invalid_argument("covariance is not positive definite");
  }
  const Eigen::Matrix<double, N, N> information =
      covariance_llt.solve(Eigen::Matrix<double, N, N>::Identity());
  // Symmetrize against round-off before the second factorization.
  const Eigen::Matrix<double, N, N> symmetric = 0.5 * (information + information.transpose());
  const Eigen::LLT<Eigen::Matrix<double, N, N>> information_llt(symmetric);
  if (information_llt.info() != Eigen::Success) {
    throw std::invalid_argument("information is not positive definite");
  }
  return information_llt.matrixU();
}

// Throws std::invalid_argument unless sigma is finite and > 0.
inline double CheckedSigma(double sigma, const char* name) {
  if (!(std::isfinite(sigma) && sigma > 0.0)) {
    throw std::invalid_argument(std::string(name) + " must be finite and > 0");
  }
  return sigma;
}

// R(yaw)^T v: a map-frame vector v expressed in a frame rotated by yaw.
template <typename T>
Eigen::Matrix<T, 2, 1> RotateMapToBody(const T& yaw_rad, const Eigen::Matrix<T, 2, 1>& v_map) {
  using std::cos;
  using std::sin;
  const T c = cos(yaw_rad);
  const T s = sin(yaw_rad);
  return Eigen::Matrix<T, 2, 1>(c * v_map.x() + s * v_map.y(), -s * v_map.x() + c * v_map.y());
}

}  // namespace parkslam::mapping

#endif  // PARKSLAM_MAPPING_COSTS_COST_UTIL_H_
