#ifndef PARKSLAM_GRAPH_MAX_MIXTURE_POSE_EDGE_FACTOR_H_
#define PARKSLAM_GRAPH_MAX_MIXTURE_POSE_EDGE_FACTOR_H_

// Max-Mixture relative-pose edge with a null hypothesis, for a loop closure
// that may be wrong (paper section III-C, "Outliers elimination using
// Max-Mixture Model"; Olson & Agarwal, "Inference on networks of mixtures for
// robust robot mapping", IJRR 2013):
//
//   p(z | x) = max( w_1 N(e; 0, Omega^-1),  w_0 N(e; 0, (s Omega)^-1) )
//
// with e the relative-pose error of pose_edge_factor.h, w_1 = 1 the edge's
// own component, w_0 = null_weight and s = null_information_scale (0 < s < 1):
// the null is the same Gaussian made very wide, "this closure carries no
// information". The negative log of component k, up to a shared constant:
//
//   N_k    = -log w_k - 0.5 log det Omega_k         (Omega_1 = Omega,
//   cost_k = N_k + 0.5 e^T Omega_k e                 Omega_0 = s Omega)
//   chosen = argmin_k cost_k
//
// so the null wins iff  e^T Omega e > 2 (N_0 - N_1) / (1 - s)
//                                   = 2 (-log w_0 - 1.5 log s) / (1 - s)
// (NullThresholdChi2). Residual (4 entries):
//
//   r = [ sqrt(s_k) U e ; sqrt(2 (N_k - N_min)) ],  s_1 = 1, s_0 = s,
//
// U^T U = Omega, N_min = min(N_0, N_1); then 0.5 ||r||^2 = cost_k - N_min,
// real and non-negative (the normalization of the mapper's Max-Mixture
// factor, mapping/costs/max_mixture_corner_factor.h). Jacobians: exact for the
// chosen component (sqrt(s_k) U de/dx, by automatic differentiation of the
// error), zero for the normalization entry, constant between switches.

#include <ceres/autodiff_cost_function.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <memory>

#include "parkslam/common/se2.h"
#include "parkslam/graph/pose_edge_factor.h"

namespace parkslam::graph {

class MaxMixturePoseEdgeFactor : public ceres::SizedCostFunction<4, 3, 3> {
 public:
  // The information must be symmetric positive definite; 0 < null_weight <= 1
  // and 0 < null_information_scale < 1, else std::invalid_argument.
  MaxMixturePoseEdgeFactor(const SE2& T_a_b_measured, const Eigen::Matrix3d& information,
                           double null_weight, double null_information_scale);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  // True when the null component is chosen at these poses.
  bool NullChosen(const double* pose_a, const double* pose_b) const;

  // The chi-square e^T Omega e above which the null is chosen.
  static double NullThresholdChi2(double null_weight, double null_information_scale);

 private:
  ceres::AutoDiffCostFunction<RelativePoseError, 3, 3, 3> error_;
  Eigen::Matrix3d information_;
  Eigen::Matrix3d sqrt_information_;
  double sqrt_null_scale_;
  double null_normalization_;  // sqrt(2 (N_0 - N_1)), with N_0 >= N_1 here
  double threshold_chi2_;
};

}  // namespace parkslam::graph

#endif  // PARKSLAM_GRAPH_MAX_MIXTURE_POSE_EDGE_FACTOR_H_
