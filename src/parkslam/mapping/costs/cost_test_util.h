#ifndef PARKSLAM_MAPPING_COSTS_COST_TEST_UTIL_H_
#define PARKSLAM_MAPPING_COSTS_COST_TEST_UTIL_H_

// Test-only helpers for the cost functions: evaluate a ceres::CostFunction on
// plain vectors and compare its Jacobians with central differences.

#include <ceres/cost_function.h>
#include <gtest/gtest.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

namespace parkslam::mapping::testing {

using Blocks = std::vector<std::vector<double>>;
using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

inline std::vector<const double*> Pointers(const Blocks& blocks) {
  std::vector<const double*> pointers;
  for (const auto& b : blocks) pointers.push_back(b.data());
  return pointers;
}

// The residual vector of cost at blocks.
inline Eigen::VectorXd Residuals(const ceres::CostFunction& cost, const Blocks& blocks) {
  Eigen::VectorXd r(cost.num_residuals());
  const std::vector<const double*> pointers = Pointers(blocks);
  EXPECT_TRUE(cost.Evaluate(pointers.data(), r.data(), nullptr));
  return r;
}

// The residual vector and every block's Jacobian (num_residuals x size).
inline std::vector<RowMajorMatrix> Jacobians(const ceres::CostFunction& cost, const Blocks& blocks,
                                             Eigen::VectorXd* residuals = nullptr) {
  const int num_r = cost.num_residuals();
  std::vector<RowMajorMatrix> jacobians;
  std::vector<double*> jacobian_pointers;
  for (const int size : cost.parameter_block_sizes()) {
    jacobians.emplace_back(RowMajorMatrix::Constant(num_r, size, 1e300));
  }
  for (auto& j : jacobians) jacobian_pointers.push_back(j.data());
  Eigen::VectorXd r(num_r);
  const std::vector<const double*> pointers = Pointers(blocks);
  EXPECT_TRUE(cost.Evaluate(pointers.data(), r.data(), jacobian_pointers.data()));
  if (residuals != nullptr) *residuals = r;
  return jacobians;
}

// Compares every Jacobian entry with a central difference of step `step` on
// each ambient coordinate: |analytic - numeric| <= tolerance * max(1, |numeric|).
inline ::testing::AssertionResult JacobiansMatchNumeric(const ceres::CostFunction& cost,
                                                        const Blocks& blocks, double step = 1e-6,
                                                        double tolerance = 1e-6) {
  const std::vector<RowMajorMatrix> analytic = Jacobians(cost, blocks);
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    for (std::size_t d = 0; d < blocks[i].size(); ++d) {
      Blocks plus = blocks, minus = blocks;
      plus[i][d] += step;
      minus[i][d] -= step;
      const Eigen::VectorXd numeric =
          (Residuals(cost, plus) - Residuals(cost, minus)) / (2.0 * step);
      for (int r = 0; r < cost.num_residuals(); ++r) {
        const double a = analytic[i](r, static_cast<Eigen::Index>(d));
        const double n = numeric(r);
        if (!(std::abs(a - n) <= tolerance * std::max(1.0, std::abs(n)))) {
          std::ostringstream message;
          message << "block " << i << " coordinate " << d << " residual " << r << ": analytic " << a
                  << " numeric " << n;
          return ::testing::AssertionFailure() << message.str();
        }
      }
    }
  }
  return ::testing::AssertionSuccess();
}

}  // namespace parkslam::mapping::testing

#endif  // PARKSLAM_MAPPING_COSTS_COST_TEST_UTIL_H_
