#include "parkslam/harness/trace_following.h"

#include <cmath>
#include <memory>
#include <stdexcept>

#include "parkslam/camera/camera_model.h"
#include "parkslam/camera/camera_names.h"
#include "parkslam/common/angles.h"
#include "parkslam/common/random.h"
#include "parkslam/control/safety_supervisor.h"
#include "parkslam/control/trace.h"
#include "parkslam/harness/dead_reckoning.h"
#include "parkslam/harness/live_cameras.h"
#include "parkslam/odometry/odometry_ekf.h"
#include "parkslam/perception/front_end.h"
#include "parkslam/sim/live_simulator.h"

namespace parkslam::harness {
namespace {

constexpr std::uint64_t kStartTag = 0x57a7;
constexpr double kTruthRecordPeriodS = 0.1;

double Square(double x) { return x * x; }

// The heading at the trace's start, from its first metre.
SE2 TraceStart(const Trajectory& trace) {
  const Eigen::Vector2d p0 = trace.front().T_map_vehicle.translation();
  for (const TimedPose& p : trace) {
    const Eigen::Vector2d d = p.T_map_vehicle.translation() - p0;
    if (d.norm() > 1.0) return SE2(p0, std::atan2(d.y(), d.x()));
  }
  return trace.front().T_map_vehicle;
}

// The controller's source of the pose: the localizer, or the dead
// reckoning started at the trace's start (the baseline).
class PoseSource {
 public:
  PoseSource(const SemanticMap& map, const TraceFollowingOptions& options,
             const odometry::OdometryEkfOptions& odometry_options, const SE2& start_map,
             const Eigen::Matrix3d& start_covariance, TimeNs t0)
      : odometry_only_(options.odometry_only) {
    if (odometry_only_) {
      ekf_ = std::make_unique<odometry::OdometryEkf>(odometry_options);
      ekf_->Initialize(t0, start_map, std::sqrt(start_covariance(2, 2)));
    } else {
      localizer_ =
          std::make_unique<localization::Localizer>(map, options.localizer, odometry_options);
      localizer_->SetPose(start_map, start_covariance);
    }
  }

  // Feeds an event; true at a camera frame (with the estimate in *pose).
  bool Process(const SensorEvent& event, SE2* pose, bool* lost, int* used = nullptr,
               int* rejected = nullptr) {
    const bool frame = std::holds_alternative<SlotObservationFrame>(event) ||
                       std::holds_alternative<TagObservationFrame>(event);
    if (odometry_only_) {
      ekf_->Process(event);
      *pose = ekf_->pose();
      *lost = false;
      return frame;
    }
    const auto estimate = localizer_->Process(event);
    if (!estimate) return false;
    *pose = estimate->T_map_vehicle;
    *lost = estimate->state != localization::LocalizerState::kTracking;
    if (used != nullptr) *used = estimate->used();
    if (rejected != nullptr) *rejected = estimate->rejected();
    return true;
  }

  SE2 Now() const { return odometry_only_ ? ekf_->pose() : localizer_->PredictedPose(); }
  // The position covariance of the last estimate (m^2).
  Eigen::Matrix2d PositionCovariance() const {
    return odometry_only_ ? Eigen::Matrix2d::Zero()
                          : Eigen::Matrix2d(localizer_->covariance().topLeftCorner<2, 2>());
  }

 private:
  bool odometry_only_;
  std::unique_ptr<odometry::OdometryEkf> ekf_;
  std::unique_ptr<localization::Localizer> localizer_;
};

// What every run of one FollowTrace shares.
struct FollowSetup {
  const sim::ScenarioConfig& scenario;
  const SemanticMap& map;
  const SE2& T_map_world;
  const control::Trace& trace;
  const TraceFollowingOptions& options;
  odometry::OdometryEkfOptions odometry_options;
  SE2 start_world;
  double cruise_mps = 0.0, timeout_s = 0.0;
  Eigen::Matrix3d start_covariance = Eigen::Matrix3d::Zero();
  const LiveCameras* cameras = nullptr;  // null: observation-level frames
  TimeNs image_period_ns = 0;
};

// Squared localization errors over a run's estimates.
struct ErrorSums {
  double position_m2 = 0.0, yaw_rad2 = 0.0;
  int n = 0;
};

// The events of one simulator step as the pose source gets them: without
// slot and tag frames in a blackout or on pixels, and on pixels with what
// the cameras see when a frame is due.
void SeenEvents(const FollowSetup& s, const sim::VehicleState& state, TimeNs* next_image_ns,
                TraceRun* run, std::vector<SensorEvent>* events) {
  const TraceFollowingOptions& options = s.options;
  const double now_s = ToSeconds(state.t_ns);
  const bool blackout = options.blackout_from_s >= 0.0 && now_s >= options.blackout_from_s &&
                        now_s < options.blackout_to_s;
  if (blackout || s.cameras != nullptr) {
    std::erase_if(*events, [](const SensorEvent& e) {
      return std::holds_alternative<SlotObservationFrame>(e) ||
             std::holds_alternative<TagObservationFrame>(e);
    });
  }
  if (s.cameras != nullptr && !blackout && state.t_ns >= *next_image_ns) {
    perception::PerceptionOutput seen = s.cameras->Perceive(state.T_map_vehicle, state.t_ns);
    events->push_back(std::move(seen.slots));
    events->push_back(std::move(seen.tags));
    *next_image_ns = state.t_ns + s.image_period_ns;
    ++run->camera_frames;
  }
}

// One autonomous run from a start drawn near the trace's start, in closed
// loop at 100 Hz: supervisor, follower, simulator, cameras, pose source.
TraceRun FollowOnce(const FollowSetup& s, int r, ErrorSums* sums) {
  const TraceFollowingOptions& options = s.options;
  const std::uint64_t seed = options.seed + static_cast<std::uint64_t>(r);
  Random rng = Random::Derive(seed, kStartTag);
  const SE2 true_start = s.start_world * SE2(rng.Gaussian(options.start_position_sigma_m),
                                             rng.Gaussian(options.start_position_sigma_m),
                                             rng.Gaussian(options.start_yaw_sigma_rad));
  sim::LiveSimulatorOptions simulator_options;
  simulator_options.dynamics = options.vehicle_dynamics;
  sim::LiveSimulator simulator(s.scenario, seed, true_start, simulator_options);
  PoseSource source(s.map, options, s.odometry_options, s.T_map_world * s.start_world,
                    s.start_covariance, simulator.time_ns());
  control::PathFollower follower(s.trace, s.scenario.vehicle, options.follower);
  // Dead reckoning alone never knows it is lost: no supervisor there.
  const bool supervised = options.safety_stop && !options.odometry_only;
  control::SafetySupervisor supervisor(options.safety);
  bool kidnapped = false;

  TraceRun run;
  const double dt_s = 1.0 / 100.0;
  double measured_speed = 0.0;
  ErrorSums own;
  TimeNs next_record_ns = 0, next_image_ns = 0;
  std::vector<SensorEvent> events;
  while (true) {
    const double t_s = ToSeconds(simulator.time_ns());
    if (options.kidnap_at_s >= 0.0 && !kidnapped && t_s >= options.kidnap_at_s) {
      // The car itself moved (not only the belief): a closed-loop kidnap.
      const Eigen::Vector3d& d = options.kidnap_offset;
      simulator.Teleport(simulator.state().T_map_vehicle * SE2(d.x(), d.y(), d.z()));
      kidnapped = true;
    }
    const double allowed_mps = supervised ? supervisor.AllowedSpeed(simulator.time_ns(), dt_s,
                                                                    s.cruise_mps, measured_speed)
                                          : s.cruise_mps;
    if (supervised && allowed_mps == 0.0) run.stopped_s += dt_s;
    const control::PathFollower::Command command =
        follower.Update(source.Now(), measured_speed, dt_s, allowed_mps);
    // While the supervisor brakes, its speed is a hard cap and the brakes
    // may work harder than the driver's comfort limit.
    const bool braking = supervised && supervisor.Braking(simulator.time_ns());
    simulator.SetMaxDecel(braking ? options.safety.brake_decel_mps2 : 0.0);
    const sim::VehicleState& state = simulator.Step(std::min(command.speed_mps, allowed_mps),
                                                    command.road_wheel_angle_rad, &events);
    if (state.t_ns >= next_record_ns) {
      run.truth_world.push_back({state.t_ns, state.T_map_vehicle});
      next_record_ns = state.t_ns + FromSeconds(kTruthRecordPeriodS);
    }
    SeenEvents(s, state, &next_image_ns, &run, &events);
    for (const SensorEvent& event : events) {
      if (const auto* w = std::get_if<WheelSpeed>(&event)) measured_speed = w->speed_mps;
      SE2 estimate;
      bool lost = false;
      int used = 1, rejected = 0;
      if (!source.Process(event, &estimate, &lost, &used, &rejected)) continue;
      supervisor.OnEstimate(EventTime(event), !lost, source.PositionCovariance(), used, rejected);
      AppendOrReplaceLast(&run.estimate_map, {EventTime(event), estimate});
      run.lost_frames += lost;
      // The truth of this frame in the map frame.
      const SE2 truth_map = s.T_map_world * simulator.state().T_map_vehicle;
      own.position_m2 += (truth_map.translation() - estimate.translation()).squaredNorm();
      own.yaw_rad2 += Square(AngleDiff(truth_map.yaw(), estimate.yaw()));
      ++own.n;
    }
    events.clear();
    run.duration_s = ToSeconds(state.t_ns);
    if (command.finished) {
      run.finished = true;
      break;
    }
    if (run.duration_s > s.timeout_s) break;
  }
  run.safety_interventions = supervisor.interventions();
  run.localization_rmse_m = own.n > 0 ? std::sqrt(own.position_m2 / own.n) : 0.0;
  run.localization_yaw_rmse_rad = own.n > 0 ? std::sqrt(own.yaw_rad2 / own.n) : 0.0;
  sums->position_m2 += own.position_m2;
  sums->yaw_rad2 += own.yaw_rad2;
  sums->n += own.n;
  return run;
}

}  // namespace

TraceFollowingResult FollowTrace(const sim::ScenarioConfig& scenario, const SemanticMap& map,
                                 const SE2& T_map_world, const Trajectory& trace_world,
                                 const TraceFollowingOptions& options,
                                 const std::function<void(int, int)>& on_run_done) {
  if (options.runs < 1) throw std::invalid_argument("runs must be at least 1");
  if (!(options.speed_kmh > 0.0 && options.speed_kmh <= 30.0)) {
    throw std::invalid_argument("speed must be in (0, 30] km/h");
  }
  if (std::holds_alternative<FromRecordedImages>(options.frames)) {
    throw std::invalid_argument(
        "trace following renders what the cameras see where the car drives; recorded images "
        "cannot be its frames");
  }
  const Trajectory trace_map = Transformed(T_map_world, trace_world);
  const control::Trace trace(trace_map);  // throws for a degenerate trace
  const double cruise_mps = options.speed_kmh / 3.6;
  Eigen::Matrix3d start_covariance = Eigen::Matrix3d::Zero();
  start_covariance.diagonal() << Square(2 * options.start_position_sigma_m),
      Square(2 * options.start_position_sigma_m), Square(2 * options.start_yaw_sigma_rad);
  FollowSetup setup{scenario,
                    map,
                    T_map_world,
                    trace,
                    options,
                    odometry::EkfOptionsFromSpec(scenario.sensors.odometry, scenario.vehicle),
                    TraceStart(trace_world),
                    cruise_mps,
                    options.timeout_factor * trace.length_m() / cruise_mps + 60.0,
                    start_covariance,
                    nullptr,
                    0};
  // The live cameras, built once: the lot is the same for every run.
  std::unique_ptr<LiveCameras> cameras;
  if (const auto* live = std::get_if<FromLiveRendering>(&options.frames)) {
    if (!(live->rate_hz > 0.0)) throw std::invalid_argument("live image rate must be > 0 Hz");
    cameras = std::make_unique<LiveCameras>(sim::BuildWorld(scenario.world), scenario.world,
                                            options.seed, options.perception);
    setup.cameras = cameras.get();
    setup.image_period_ns = FromSeconds(1.0 / live->rate_hz);
  }

  TraceFollowingResult result;
  ErrorSums sums;
  for (int r = 0; r < options.runs; ++r) {
    result.runs.push_back(FollowOnce(setup, r, &sums));
    if (on_run_done) on_run_done(r + 1, options.runs);
  }
  std::vector<Trajectory> truths;
  for (const TraceRun& run : result.runs) truths.push_back(run.truth_world);
  result.metrics = eval::EvaluateTraceFollowing(trace_world, truths, 0.5, options.skip_start_m,
                                                options.skip_end_m);
  result.localization_rmse_m = sums.n > 0 ? std::sqrt(sums.position_m2 / sums.n) : 0.0;
  result.localization_yaw_rmse_rad = sums.n > 0 ? std::sqrt(sums.yaw_rad2 / sums.n) : 0.0;
  return result;
}

}  // namespace parkslam::harness
