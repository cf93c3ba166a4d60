#ifndef PARKSLAM_HARNESS_TRACE_FOLLOWING_H_
#define PARKSLAM_HARNESS_TRACE_FOLLOWING_H_

// The paper's online experiment (IV-B) in the simulator: a recorded trace is
// followed autonomously, again and again. The simulator senses from the
// TRUE pose; the localizer (or, as the baseline, the dead reckoning alone)
// estimates the pose on the map; a path follower steers the simulated car
// along the trace from that estimate. Each run's true trajectory is kept,
// and the runs are compared with the trace and with one another.

#include <cstdint>
#include <functional>
#include <vector>

#include "parkslam/common/trajectory.h"
#include "parkslam/control/path_follower.h"
#include "parkslam/control/safety_supervisor.h"
#include "parkslam/eval/trace_metrics.h"
#include "parkslam/harness/sensor_stream.h"
#include "parkslam/localization/localizer.h"
#include "parkslam/map/semantic_map.h"
#include "parkslam/perception/front_end.h"
#include "parkslam/sim/live_simulator.h"
#include "parkslam/sim/scenario_config.h"

namespace parkslam::harness {

struct TraceFollowingOptions {
  int runs = 10;
  double speed_kmh = 4.0;
  std::uint64_t seed = 1;      // run r uses seed + r
  bool odometry_only = false;  // steer from dead reckoning alone
  // The car starts near the trace's start: this far off, and the localizer
  // is told the trace's start with this uncertainty.
  double start_position_sigma_m = 0.2;
  double start_yaw_sigma_rad = 0.03;
  double timeout_factor = 2.0;  // give up after factor x (length / speed) + 60 s
  // Stations of the repeatability measure skip the start (the car is
  // still converging from its offset start) and the very end.
  double skip_start_m = 5.0;
  double skip_end_m = 2.0;
  // The pose source's slot and tag frames: the live simulator's
  // observation-level ones, or frame sets the cameras render at a rate from
  // the true pose, through the front end (nothing is written). Recorded
  // images cannot be: the car drives where its controller takes it.
  FrameSource frames = FromObservations{};
  perception::PerceptionOptions perception;  // the front end on those frames
  control::PathFollowerOptions follower;
  localization::LocalizerOptions localizer;
  // The car brakes to a stop when localization is lost, too uncertain or
  // stale, and goes on when it is back (control/safety_supervisor.h).
  bool safety_stop = true;
  control::SafetyOptions safety;
  // Faults for tests (times from the run's start; < 0: none): the car
  // itself jumps by kidnap_offset (x, y, yaw in its own frame) at
  // kidnap_at_s; no slot or tag frame is seen in [blackout_from_s,
  // blackout_to_s).
  double kidnap_at_s = -1.0;
  Eigen::Vector3d kidnap_offset = Eigen::Vector3d::Zero();
  double blackout_from_s = -1.0, blackout_to_s = -1.0;
  // The car between the commands and the road: ideal (all zero) or a real
  // car's delay, lags and tyre slip (sim::RealisticDynamics()).
  sim::VehicleDynamics vehicle_dynamics;
};

struct TraceRun {
  Trajectory truth_world;   // the true trajectory, 10 Hz
  Trajectory estimate_map;  // the pose the controller steered by, at camera frames
  bool finished = false;
  double duration_s = 0.0;
  double localization_rmse_m = 0.0;  // estimate against truth, map frame
  double localization_yaw_rmse_rad = 0.0;
  int lost_frames = 0;
  int camera_frames = 0;         // rendered live
  int safety_interventions = 0;  // times the supervisor made the car stop
  double stopped_s = 0.0;        // time held at a standstill by it
};

struct TraceFollowingResult {
  std::vector<TraceRun> runs;
  eval::TraceFollowingMetrics metrics;  // true runs against the trace, world frame
  double localization_rmse_m = 0.0;     // over all runs
  double localization_yaw_rmse_rad = 0.0;
};

// trace_world: the trace in the simulator's (world) frame. T_map_world maps
// the world into the map's frame (the map may have been built in its own
// frame); the controller and localizer work in the map frame.
TraceFollowingResult FollowTrace(const sim::ScenarioConfig& scenario, const SemanticMap& map,
                                 const SE2& T_map_world, const Trajectory& trace_world,
                                 const TraceFollowingOptions& options,
                                 const std::function<void(int run, int runs)>& on_run_done = {});

}  // namespace parkslam::harness

#endif  // PARKSLAM_HARNESS_TRACE_FOLLOWING_H_
