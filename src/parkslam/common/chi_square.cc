#include "parkslam/common/chi_square.h"

#include <cmath>
#include <stdexcept>

namespace parkslam {
namespace {

constexpr double kRelativeTolerance = 1e-15;
// Both expansions need O(sqrt(a)) terms near x = a; this covers a up to ~1e7.
constexpr int kMaxIterations = 100000;

// log(x^a e^-x / Gamma(a)), the common prefactor of both expansions.
double LogPrefactor(double a, double x) { return a * std::log(x) - x - std::lgamma(a); }

// P(a, x) by its power series, for x < a + 1 (Numerical Recipes 6.2.5 form):
// P = x^a e^-x / Gamma(a + 1) * sum_n x^n / ((a + 1) ... (a + n)).
double LowerGammaSeries(double a, double x) {
  double term = 1.0 / a;
  double sum = term;
  for (int n = 1; n < kMaxIterations; ++n) {
    term *= x / (a + n);
    sum += term;
    if (std::abs(term) < std::abs(sum) * kRelativeTolerance) break;
  }
  return sum * std::exp(LogPrefactor(a, x));
}

// Q(a, x) = 1 - P(a, x) by its continued fraction (modified Lentz), for
// x >= a + 1.
double UpperGammaContinuedFraction(double a, double x) {
  constexpr double kTiny = 1e-300;
  double b = x + 1.0 - a;
  double c = 1.0 / kTiny;
  double d = 1.0 / b;
  double h = d;
  for (int n = 1; n < kMaxIterations; ++n) {
    const double an = -n * (n - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < kRelativeTolerance) break;
  }
  return std::exp(LogPrefactor(a, x)) * h;
}

}  // namespace

double RegularizedLowerGamma(double a, double x) {
  if (!(a > 0.0) || !(x >= 0.0)) {
    throw std::invalid_argument("RegularizedLowerGamma: needs a > 0, x >= 0");
  }
  if (x == 0.0) return 0.0;
  if (x < a + 1.0) return LowerGammaSeries(a, x);
  return 1.0 - UpperGammaContinuedFraction(a, x);
}

double ChiSquareQuantile(double p, int dof) {
  if (!(p > 0.0 && p < 1.0) || dof < 1) {
    throw std::invalid_argument("ChiSquareQuantile: needs 0 < p < 1 and dof >= 1");
  }
  const double a = 0.5 * dof;
  auto cdf = [a](double x) { return RegularizedLowerGamma(a, 0.5 * x); };
  double lower = 0.0;
  double upper = dof + 10.0 * std::sqrt(2.0 * dof) + 10.0;
  while (cdf(upper) < p) upper *= 2.0;
  // Bisection: the CDF is monotone, and 200 halvings reach double precision
  // from any bracket, including quantiles near 0 for dof 1.
  for (int i = 0; i < 200 && upper - lower > 1e-12 * upper; ++i) {
    const double middle = 0.5 * (lower + upper);
    if (cdf(middle) < p) {
      lower = middle;
    } else {
      upper = middle;
    }
  }
  return 0.5 * (lower + upper);
}

}  // namespace parkslam
