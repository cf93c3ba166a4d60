#include "parkslam/eval/trace_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

namespace parkslam::eval {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Consecutive positions closer than this are one point.
constexpr double kMinPointSpacingM = 0.01;
constexpr double kMinTraceLengthM = 1.0;
// A run crossing farther than this from the station does not cover it.
constexpr double kMaxOffsetM = 5.0;
// A run segment must head within 60 degrees of the trace to count.
constexpr double kMinDirectionCosine = 0.5;
// Run path searched beyond the trace distance since the last match.
constexpr double kSearchSlackM = 10.0;
// The station's tangent is the chord over +-this much trace.
constexpr double kTangentHalfWindowM = 0.25;

// A polyline through positions with its cumulative arc lengths.
struct Polyline {
  std::vector<Eigen::Vector2d> points_m;
  std::vector<double> s_m;

  explicit Polyline(const Trajectory& trajectory) {
    for (const TimedPose& pose : trajectory) {
      const Eigen::Vector2d& p = pose.T_map_vehicle.translation();
      if (points_m.empty() || (p - points_m.back()).norm() >= kMinPointSpacingM) {
        s_m.push_back(points_m.empty() ? 0.0 : s_m.back() + (p - points_m.back()).norm());
        points_m.push_back(p);
      }
    }
  }

  size_t segments() const { return points_m.size() < 2 ? 0 : points_m.size() - 1; }
  double length_m() const { return s_m.empty() ? 0.0 : s_m.back(); }

  Eigen::Vector2d PointAt(double s) const {
    s = std::clamp(s, 0.0, length_m());
    const auto after = std::upper_bound(s_m.begin(), s_m.end(), s);
    const size_t i = std::min<size_t>(
        static_cast<size_t>(std::max<std::ptrdiff_t>(0, after - s_m.begin() - 1)), segments() - 1);
    const double fraction = (s - s_m[i]) / (s_m[i + 1] - s_m[i]);
    return points_m[i] + fraction * (points_m[i + 1] - points_m[i]);
  }
};

// A station: a point on the trace and its unit tangent and left normal.
struct Station {
  double s_m = 0.0;
  Eigen::Vector2d point_m;
  Eigen::Vector2d tangent;
  Eigen::Vector2d normal;
};

Station MakeStation(const Polyline& trace, double s_m) {
  Station station;
  station.s_m = s_m;
  station.point_m = trace.PointAt(s_m);
  const Eigen::Vector2d chord =
      trace.PointAt(s_m + kTangentHalfWindowM) - trace.PointAt(s_m - kTangentHalfWindowM);
  station.tangent = chord.normalized();
  station.normal = Eigen::Vector2d(-station.tangent.y(), station.tangent.x());
  return station;
}

// Where run segment i crosses the station's normal line: the signed offset
// along the normal and the fraction along the segment.
struct Crossing {
  double offset_m = 0.0;
  double fraction = 0.0;
};

std::optional<Crossing> CrossSegment(const Station& station, const Polyline& run, size_t i) {
  const Eigen::Vector2d& a = run.points_m[i];
  const Eigen::Vector2d d = run.points_m[i + 1] - a;
  // The point a + mu d lies on the normal line where (a + mu d - P) . t = 0.
  const double along = d.dot(station.tangent);
  if (!(along > kMinDirectionCosine * d.norm())) return std::nullopt;
  const double mu = (station.point_m - a).dot(station.tangent) / along;
  if (mu < 0.0 || mu > 1.0) return std::nullopt;
  const double offset_m = (a + mu * d - station.point_m).dot(station.normal);
  if (std::abs(offset_m) > kMaxOffsetM) return std::nullopt;
  return Crossing{offset_m, mu};
}

// Matches one run to the stations in order (see the header).
std::vector<double> MatchRun(const std::vector<Station>& stations, const Polyline& run) {
  std::vector<double> offsets_m(stations.size(), kNaN);
  bool acquired = false;
  size_t progress = 0;            // run segment of the last match
  double run_s_last_m = 0.0;      // run arc length at the last match
  double station_s_last_m = 0.0;  // trace arc length of the last matched station
  for (size_t k = 0; k < stations.size() && run.segments() > 0; ++k) {
    const Station& station = stations[k];
    size_t first = progress;
    double window_end_m = run_s_last_m + (station.s_m - station_s_last_m) + kSearchSlackM;
    if (!acquired) {
      // Not matched yet: the run's first crossing anywhere opens the window.
      while (first < run.segments() && !CrossSegment(station, run, first)) ++first;
      if (first == run.segments()) continue;
      window_end_m = run.s_m[first] + kSearchSlackM;
    }
    std::optional<Crossing> best;
    size_t best_i = first;
    for (size_t i = first; i < run.segments() && run.s_m[i] <= window_end_m; ++i) {
      const std::optional<Crossing> crossing = CrossSegment(station, run, i);
      if (crossing && (!best || std::abs(crossing->offset_m) < std::abs(best->offset_m))) {
        best = crossing;
        best_i = i;
      }
    }
    if (!best) continue;
    offsets_m[k] = best->offset_m;
    acquired = true;
    progress = best_i;
    run_s_last_m = run.s_m[best_i] + best->fraction * (run.s_m[best_i + 1] - run.s_m[best_i]);
    station_s_last_m = station.s_m;
  }
  return offsets_m;
}

void Validate(const Polyline& trace, size_t runs, double station_spacing_m, double skip_start_m,
              double skip_end_m) {
  if (runs < 1) throw std::invalid_argument("EvaluateTraceFollowing: no run");
  if (trace.segments() < 1 || trace.length_m() < kMinTraceLengthM) {
    throw std::invalid_argument("EvaluateTraceFollowing: trace shorter than 1 m");
  }
  if (!(station_spacing_m > 0.0)) {
    throw std::invalid_argument("EvaluateTraceFollowing: station_spacing_m must be > 0");
  }
  if (!(skip_start_m >= 0.0) || !(skip_end_m >= 0.0)) {
    throw std::invalid_argument("EvaluateTraceFollowing: skips must be >= 0");
  }
  if (skip_start_m > trace.length_m() - skip_end_m) {
    throw std::invalid_argument("EvaluateTraceFollowing: skips leave no station");
  }
}

// The stations along the trace, skip_start_m - k spacing first: the
// skipped start is still matched, at the same spacing, so that each run's
// progress reaches the first reported station in order. Sets the reported
// stations' arc lengths; returns the stations, *skipped of them unreported.
std::vector<Station> MakeStations(const Polyline& trace_line, double station_spacing_m,
                                  double skip_start_m, double skip_end_m, size_t* skipped,
                                  TraceFollowingMetrics* metrics) {
  std::vector<Station> stations;
  for (int k = static_cast<int>(std::floor(skip_start_m / station_spacing_m)); k >= 1; --k) {
    stations.push_back(MakeStation(trace_line, skip_start_m - k * station_spacing_m));
  }
  *skipped = stations.size();
  const double last_m = trace_line.length_m() - skip_end_m;
  for (int k = 0;; ++k) {
    const double s_m = skip_start_m + k * station_spacing_m;
    if (s_m > last_m + 1e-9) break;
    stations.push_back(MakeStation(trace_line, std::min(s_m, last_m)));
    metrics->station_s_m.push_back(stations.back().s_m);
  }
  metrics->stations = static_cast<int>(metrics->station_s_m.size());
  return stations;
}

// Per run: mean and max of |offset| over the stations it covers.
void AddLateralDeviations(const std::vector<Station>& stations, size_t skipped,
                          const std::vector<Trajectory>& runs, TraceFollowingMetrics* out) {
  TraceFollowingMetrics& metrics = *out;
  double mean_sum_m = 0.0;
  int runs_covering = 0;
  metrics.lateral_max_all_m = kNaN;
  for (const Trajectory& run : runs) {
    const std::vector<double> all_offsets_m = MatchRun(stations, Polyline(run));
    std::vector<double> offsets_m(all_offsets_m.begin() + static_cast<std::ptrdiff_t>(skipped),
                                  all_offsets_m.end());
    double sum_m = 0.0;
    double max_m = 0.0;
    int covered = 0;
    for (double offset_m : offsets_m) {
      if (std::isnan(offset_m)) continue;
      sum_m += std::abs(offset_m);
      max_m = std::max(max_m, std::abs(offset_m));
      ++covered;
    }
    metrics.lateral_mean_m.push_back(covered > 0 ? sum_m / covered : kNaN);
    metrics.lateral_max_m.push_back(covered > 0 ? max_m : kNaN);
    if (covered > 0) {
      mean_sum_m += metrics.lateral_mean_m.back();
      ++runs_covering;
      metrics.lateral_max_all_m = std::isnan(metrics.lateral_max_all_m)
                                      ? max_m
                                      : std::max(metrics.lateral_max_all_m, max_m);
    }
    metrics.lateral_offset_m.push_back(std::move(offsets_m));
  }
  metrics.lateral_mean_all_m = runs_covering > 0 ? mean_sum_m / runs_covering : kNaN;
}

// Per station: the spread of the signed offset across the runs covering it.
void AddRepeatSpread(TraceFollowingMetrics* out) {
  TraceFollowingMetrics& metrics = *out;
  double variance_sum_m2 = 0.0;
  metrics.repeat_std_max_m = 0.0;
  for (size_t k = 0; k < metrics.station_s_m.size(); ++k) {
    double sum_m = 0.0;
    int n = 0;
    for (const std::vector<double>& offsets_m : metrics.lateral_offset_m) {
      if (std::isnan(offsets_m[k])) continue;
      sum_m += offsets_m[k];
      ++n;
    }
    if (n < 2) continue;
    const double mean_m = sum_m / n;
    double squares_m2 = 0.0;
    for (const std::vector<double>& offsets_m : metrics.lateral_offset_m) {
      if (!std::isnan(offsets_m[k]))
        squares_m2 += (offsets_m[k] - mean_m) * (offsets_m[k] - mean_m);
    }
    const double variance_m2 = squares_m2 / n;
    variance_sum_m2 += variance_m2;
    metrics.repeat_std_max_m = std::max(metrics.repeat_std_max_m, std::sqrt(variance_m2));
    ++metrics.repeat_stations;
  }
  if (metrics.repeat_stations > 0) {
    metrics.repeat_std_m = std::sqrt(variance_sum_m2 / metrics.repeat_stations);
  } else {
    metrics.repeat_std_m = kNaN;
    metrics.repeat_std_max_m = kNaN;
  }
}

}  // namespace

TraceFollowingMetrics EvaluateTraceFollowing(const Trajectory& trace,
                                             const std::vector<Trajectory>& runs,
                                             double station_spacing_m, double skip_start_m,
                                             double skip_end_m) {
  const Polyline trace_line(trace);
  Validate(trace_line, runs.size(), station_spacing_m, skip_start_m, skip_end_m);

  TraceFollowingMetrics metrics;
  metrics.runs = static_cast<int>(runs.size());
  metrics.station_spacing_m = station_spacing_m;
  size_t skipped = 0;
  const std::vector<Station> stations =
      MakeStations(trace_line, station_spacing_m, skip_start_m, skip_end_m, &skipped, &metrics);
  AddLateralDeviations(stations, skipped, runs, &metrics);
  AddRepeatSpread(&metrics);
  return metrics;
}

}  // namespace parkslam::eval
