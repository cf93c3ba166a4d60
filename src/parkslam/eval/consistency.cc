#include "parkslam/eval/consistency.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cstddef>
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

double IntegratedAutocorrelationTime(const std::vector<double>& series) {
  const size_t n = series.size();
  if (n < 2) return 1.0;
  double mean = 0.0;
  for (const double v : series) mean += v;
  mean /= static_cast<double>(n);
  const auto autocovariance = [&](size_t lag) {
    double sum = 0.0;
    for (size_t i = 0; i + lag < n; ++i) sum += (series[i] - mean) * (series[i + lag] - mean);
    return sum / static_cast<double>(n);
  };
  const double variance = autocovariance(0);
  if (!(variance > 0.0)) return 1.0;
  constexpr double kWindowFactor = 5.0;
  // Beyond this lag the time is cut short (and the band it gives narrower):
  // the cost stays linear in the drive's length.
  constexpr size_t kMaxLag = 5000;
  double time = 1.0;
  for (size_t lag = 1; lag < std::min(n, kMaxLag); ++lag) {
    time += 2.0 * autocovariance(lag) / variance;
    if (static_cast<double>(lag) >= kWindowFactor * time) break;
  }
  return std::max(time, 1.0);
}

NeesSummary SummarizeNees(std::vector<double> nees, int dof, double confidence) {
  NeesSummary summary;
  summary.frame_band = AverageNeesBand(dof, 1, confidence);
  if (nees.empty()) return summary;
  summary.frames = static_cast<int>(nees.size());
  summary.mean_band = AverageNeesBand(dof, summary.frames, confidence);
  double sum = 0.0;
  int inside = 0;
  for (const double v : nees) {
    sum += v;
    inside += v >= summary.frame_band.lower && v <= summary.frame_band.upper;
  }
  summary.mean = sum / summary.frames;
  summary.effective_frames =
      std::max(1, static_cast<int>(summary.frames / IntegratedAutocorrelationTime(nees)));
  summary.effective_mean_band = AverageNeesBand(dof, summary.effective_frames, confidence);
  summary.share_inside_frame_band = static_cast<double>(inside) / summary.frames;
  const size_t mid = nees.size() / 2;
  std::nth_element(nees.begin(), nees.begin() + static_cast<std::ptrdiff_t>(mid), nees.end());
  summary.median = nees[mid];
  return summary;
}

}  // namespace parkslam::eval
