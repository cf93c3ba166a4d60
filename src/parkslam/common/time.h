#ifndef PARKSLAM_COMMON_TIME_H_
#define PARKSLAM_COMMON_TIME_H_

#include <cmath>
#include <cstdint>

namespace parkslam {

// Time is an integer count of nanoseconds since the start of a recording (DESIGN.md 3).
using TimeNs = std::int64_t;

inline constexpr TimeNs kNanosecondsPerSecond = 1'000'000'000;

inline constexpr double ToSeconds(TimeNs t_ns) { return static_cast<double>(t_ns) * 1e-9; }

inline TimeNs FromSeconds(double t_s) { return static_cast<TimeNs>(std::llround(t_s * 1e9)); }

}  // namespace parkslam

#endif  // PARKSLAM_COMMON_TIME_H_
