#include "parkslam/eval/consistency.h"

#include <Eigen/Cholesky>
#include <stdexcept>

#include "parkslam/common/chi_square.h"

namespace parkslam::eval {

double Nees(const Eigen::Vector3d& error, const Eigen::Matrix3d& covariance) {
  return error.dot(covariance.ldlt().solve(error));
}

NeesBand AverageNeesBand(int dof, int runs, double confidence) {
  if (dof < 1 || runs < 1 || !(confidence > 0.0 && confidence < 1.0)) {
    throw std::invalid_argument(
        "AverageNeesBand: needs dof >= 1, runs >= 1 and 0 < confidence < 1");
  }
  const int total_dof = dof * runs;
  const double n = static_cast<double>(runs);
  return {ChiSquareQuantile(0.5 * (1.0 - confidence), total_dof) / n,
          ChiSquareQuantile(0.5 * (1.0 + confidence), total_dof) / n};
}

}  // namespace parkslam::eval
