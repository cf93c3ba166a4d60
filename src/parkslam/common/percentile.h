#ifndef PARKSLAM_COMMON_PERCENTILE_H_
#define PARKSLAM_COMMON_PERCENTILE_H_

// The quantiles that timing summaries quote (benchmarks, the live node).

#include <algorithm>
#include <cstddef>
#include <vector>

namespace parkslam {

// The q-quantile of v (the element at rank q n, the largest for q = 1); 0
// for none.
inline double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())))];
}

}  // namespace parkslam

#endif  // PARKSLAM_COMMON_PERCENTILE_H_
