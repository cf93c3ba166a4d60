#ifndef PARKSLAM_EVAL_TRACE_METRICS_H_
#define PARKSLAM_EVAL_TRACE_METRICS_H_

#include <vector>

#include "parkslam/common/trajectory.h"

namespace parkslam::eval {

// How closely repeated autonomous drives follow a recorded trace (paper IV-B:
// the car follows the pre-recorded human trace more than ten times; the
// standard deviation of the repeated traces is the system accuracy).
struct TraceFollowingMetrics {
  int runs = 0;
  double station_spacing_m = 0.5;
  int stations = 0;
  std::vector<double> lateral_mean_m;  // per run: mean |lateral offset| over stations
  std::vector<double> lateral_max_m;   // per run: max |lateral offset|
  double lateral_mean_all_m = 0.0;     // mean over runs of lateral_mean_m
  double lateral_max_all_m = 0.0;      // max over runs of lateral_max_m
  // RMS over stations of the across-run standard deviation of the signed
  // lateral offset (the paper's figure); population standard deviation
  // (divides by the number of runs at the station).
  double repeat_std_m = 0.0;
  double repeat_std_max_m = 0.0;  // max over stations
  // Stations covered by at least 2 runs: those in repeat_std_m.
  int repeat_stations = 0;
  // Arc length of each station along the trace.
  std::vector<double> station_s_m;
  // [run][station]: signed lateral offset, left of the trace positive; NaN
  // where the run does not cover the station.
  std::vector<std::vector<double>> lateral_offset_m;
};

// Stations every station_spacing_m along the trace's positions, from
// skip_start_m to length - skip_end_m. At each station the run's offset is
// where its polyline crosses the trace's normal line there: the crossing
// nearest the station, at most 5 m away, by a run segment heading within 60
// degrees of the trace. A run is matched in order: each station searches
// forward from the run's last match, over the trace distance since that match
// plus 10 m of run path, so a trace that passes the same place twice matches
// each pass to its own pass; the skipped start is matched too, only not
// reported. A station no run segment crosses is missing for
// that run: excluded from its statistics, and from the standard deviation at
// that station, which needs at least 2 runs. Statistics with nothing to
// average are NaN. Throws std::invalid_argument for no run, a trace shorter
// than 1 m, a non-positive spacing, negative skips or skips that leave no
// station.
TraceFollowingMetrics EvaluateTraceFollowing(const Trajectory& trace,
                                             const std::vector<Trajectory>& runs,
                                             double station_spacing_m = 0.5,
                                             double skip_start_m = 0.0, double skip_end_m = 0.0);

}  // namespace parkslam::eval

#endif  // PARKSLAM_EVAL_TRACE_METRICS_H_
