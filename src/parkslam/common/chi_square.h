#ifndef PARKSLAM_COMMON_CHI_SQUARE_H_
#define PARKSLAM_COMMON_CHI_SQUARE_H_

// The chi-square distribution's quantile, used for validation gates (the
// localizer) and for consistency bands (eval).

namespace parkslam {

// The p-quantile of the chi-square distribution with dof degrees of freedom:
// the x with P(dof / 2, x / 2) = p for the regularised lower incomplete gamma
// function P. Solved by bisection to about 1e-12 relative. Throws
// std::invalid_argument unless 0 < p < 1 and dof >= 1.
double ChiSquareQuantile(double p, int dof);

// The regularised lower incomplete gamma function P(a, x), a > 0, x >= 0.
double RegularizedLowerGamma(double a, double x);

}  // namespace parkslam

#endif  // PARKSLAM_COMMON_CHI_SQUARE_H_
