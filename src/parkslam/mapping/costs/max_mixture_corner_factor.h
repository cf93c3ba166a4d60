#ifndef PARKSLAM_MAPPING_COSTS_MAX_MIXTURE_CORNER_FACTOR_H_
#define PARKSLAM_MAPPING_COSTS_MAX_MIXTURE_CORNER_FACTOR_H_

// Max-Mixture factor for an ambiguous slot association (section III-C,
// "Outliers elimination using Max-Mixture Model": p(z|x) = max_k w_k N(mu_k,
// Lambda_k^-1); Olson & Agarwal 2013; Pfingsthorn & Birk 2014). All candidates
// enter the graph; only the component of minimum cost is kept.
//
// One slot observation measured J corners z_j (vehicle frame, covariance
// Sigma_j, U_j = (Sigma_j^-1).llt().matrixU()). Component k = 0..K-1 is the
// hypothesis that measured corner j is corner c_kj of candidate slot k; the
// null component (weight w_null, optional) is "new slot or outlier".
//
//   e_kj    = U_j (R(yaw)^T (c_kj - t) - z_j)                      (2-vector)
//   chi2_k  = sum_j ||e_kj||^2
//   cost_k  = -log(w_k) + 0.5 chi2_k          (the log-det term is shared by
//                                              all candidates and drops out)
//   cost_0  = -log(w_null) + 0.5 null_chi2    (null: flat, no landmark)
//   chosen  = argmin over components of cost  (ties: see ChosenComponent)
//
// Residual (2J + 1 entries):
//   r = [ e_chosen,0 ; ... ; e_chosen,J-1 ; sqrt(2 (N_chosen - N_min)) ]
// with zeros in place of e for the null, N_k = -log(w_k),
// N_null = -log(w_null) + 0.5 null_chi2, N_min = min over all components N.
// So r is real (N_chosen >= N_min) and 0.5 ||r||^2 = cost_chosen - N_min
// (DESIGN.md section 5, the libRSF normalization).
//
// Jacobians: exact for the pose and for the J corners of the chosen candidate;
// zero for every other candidate's corners, zero for all blocks when the null
// is chosen, and zero for the normalization entry (it is constant between
// switches). With q = R(yaw)^T (c_kj - t):
//   d e_kj / d t   = -U_j R^T
//   d e_kj / d yaw =  U_j [q_y ; -q_x]
//   d e_kj / d c   =  U_j R^T
//
// Acceptance threshold: one candidate of weight w beats the null iff
//   cost_k < cost_null  <=>  chi2 < null_chi2 + 2 log(w / w_null)
// (CandidateAcceptanceChi2); of two candidates, k beats l iff
//   chi2_k - chi2_l < 2 log(w_k / w_l)    (strict; a tie keeps the lower index).

#include <ceres/cost_function.h>

#include <Eigen/Core>

#include <vector>

namespace parkslam::mapping {

// One measured slot corner in the vehicle frame.
struct CornerMeasurement {
  Eigen::Vector2d z_vehicle = Eigen::Vector2d::Zero();       // metres
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Identity();  // m^2
};

class MaxMixtureCornerFactor : public ceres::CostFunction {
 public:
  // ChosenComponent's value for the null component.
  static constexpr int kNullComponent = -1;

  // measurements: J >= 1 measured corners. candidate_weights: K >= 1 weights,
  // each finite and > 0 (they need not sum to one). null_weight: >= 0, 0 means
  // no null component. null_chi2: >= 0, the chi2 level of the null component.
  // Parameter blocks: [pose (3), then for k = 0..K-1, for j = 0..J-1 the corner
  // (2) of candidate k that measurement j refers to] -- see CornerBlockIndex.
  // Throws std::invalid_argument on invalid input.
  MaxMixtureCornerFactor(std::vector<CornerMeasurement> measurements,
                         std::vector<double> candidate_weights, double null_weight,
                         double null_chi2);

  static MaxMixtureCornerFactor* Create(std::vector<CornerMeasurement> measurements,
                                        std::vector<double> candidate_weights, double null_weight,
                                        double null_chi2);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  // The component of minimum cost at these parameters: k in [0, K) or
  // kNullComponent. Ties: a candidate is chosen over the null only when it is
  // strictly cheaper (the null keeps a tie, matching CandidateAcceptanceChi2's
  // strict "<"); among candidates of equal cost the lowest index wins.
  int ChosenComponent(double const* const* parameters) const;

  // chi2_k = sum_j ||e_kj||^2 of candidate k at these parameters.
  double CandidateChi2(double const* const* parameters, int candidate) const;

  // cost of a component (k in [0, K), or kNullComponent) at these parameters:
  // -log(w_k) + 0.5 chi2_k, or -log(w_null) + 0.5 null_chi2.
  double ComponentCost(double const* const* parameters, int component) const;

  // N_min = min over components of N (see the header comment); 0.5 ||r||^2 =
  // ComponentCost(chosen) - MinNormalization().
  double MinNormalization() const { return min_normalization_; }

  // A single candidate of weight w beats the null iff its chi2 is below
  // null_chi2 + 2 log(candidate_weight / null_weight). null_weight > 0.
  static double CandidateAcceptanceChi2(double candidate_weight, double null_weight,
                                        double null_chi2);

  // Index into the parameter-block list of the corner of candidate k that
  // measurement j refers to: 1 + k * J + j (block 0 is the pose).
  int CornerBlockIndex(int candidate, int measurement) const {
    return 1 + candidate * num_measurements() + measurement;
  }

  int num_measurements() const { return static_cast<int>(z_vehicle_m_.size()); }
  int num_candidates() const { return static_cast<int>(negative_log_weights_.size()); }
  bool has_null() const { return has_null_; }

 private:
  // Whitened error of measurement j against corner c, and its chi2.
  Eigen::Vector2d WhitenedError(const double* pose, const double* corner, int measurement) const;
  int Choose(double const* const* parameters) const;

  std::vector<Eigen::Vector2d> z_vehicle_m_;
  std::vector<Eigen::Matrix2d> sqrt_information_;
  std::vector<double> negative_log_weights_;  // N_k for k in [0, K)
  bool has_null_ = false;
  double null_cost_ = 0.0;  // N_null = cost_null (constant)
  double min_normalization_ = 0.0;
};

}  // namespace parkslam::mapping

#endif  // PARKSLAM_MAPPING_COSTS_MAX_MIXTURE_CORNER_FACTOR_H_
