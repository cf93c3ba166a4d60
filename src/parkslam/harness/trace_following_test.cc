#include "parkslam/harness/trace_following.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>

#include "parkslam/common/random.h"
#include "parkslam/sim/world.h"

#include "parkslam/harness/dead_reckoning.h"
#include "parkslam/harness/kidnap.h"
#include "parkslam/sim/route.h"
#include "parkslam/sim/simulator.h"

namespace parkslam::harness {
namespace {

// The default lot with a short drive: the corridor, aisle 1, up the east
// cross aisle and back west through aisle 3 (no laps).
sim::ScenarioConfig ShortScenario() {
  sim::ScenarioConfig scenario = sim::DefaultScenario();
  scenario.route.laps = 0;
  return scenario;
}

Trajectory HumanDrive(const sim::ScenarioConfig& scenario) {
  Trajectory trace;
  for (const sim::VehicleState& s : sim::DriveRoute(scenario.route, scenario.vehicle, 1)) {
    trace.push_back({s.t_ns, s.T_map_vehicle});
  }
  return trace;
}

SemanticMap TrueMap(const sim::ScenarioConfig& scenario) {
  return sim::ToSemanticMap(sim::BuildWorld(scenario.world));
}

TEST(TraceFollowingTest, LocalizedRunsRepeatTheTraceClosely) {
  const sim::ScenarioConfig scenario = ShortScenario();
  TraceFollowingOptions options;
  options.runs = 3;
  options.speed_kmh = 10.0;
  const TraceFollowingResult r =
      FollowTrace(scenario, TrueMap(scenario), SE2(), HumanDrive(scenario), options);
  ASSERT_EQ(r.runs.size(), 3u);
  for (const TraceRun& run : r.runs) {
    EXPECT_TRUE(run.finished);
    EXPECT_EQ(run.lost_frames, 0);
    EXPECT_EQ(run.safety_interventions, 0);  // the supervisor never stops a healthy run
  }
  EXPECT_LT(r.metrics.repeat_std_m, 0.05);
  EXPECT_LT(r.metrics.lateral_mean_all_m, 0.10);
  EXPECT_LT(r.localization_rmse_m, 0.10);
}

// The targets with a real car's actuator delay, speed lag and tyre
// slip (sim::RealisticDynamics): std <= 0.05 m, lateral mean <= 0.10 m.
TEST(TraceFollowingTest, RealisticVehicleRepeatsTheTraceAt4And10Kmh) {
  const sim::ScenarioConfig scenario = ShortScenario();
  for (const double kmh : {4.0, 10.0}) {
    TraceFollowingOptions options;
    options.runs = 3;
    options.speed_kmh = kmh;
    options.vehicle_dynamics = sim::RealisticDynamics();
    const TraceFollowingResult r =
        FollowTrace(scenario, TrueMap(scenario), SE2(), HumanDrive(scenario), options);
    for (const TraceRun& run : r.runs) EXPECT_TRUE(run.finished) << kmh << " km/h";
    EXPECT_LE(r.metrics.repeat_std_m, 0.05) << kmh << " km/h";
    EXPECT_LE(r.metrics.lateral_mean_all_m, 0.10) << kmh << " km/h";
  }
}

TEST(TraceFollowingTest, DeadReckoningAloneDriftsAway) {
  const sim::ScenarioConfig scenario = ShortScenario();
  TraceFollowingOptions options;
  options.runs = 3;
  options.speed_kmh = 10.0;
  const TraceFollowingResult localized =
      FollowTrace(scenario, TrueMap(scenario), SE2(), HumanDrive(scenario), options);
  options.odometry_only = true;
  const TraceFollowingResult blind =
      FollowTrace(scenario, TrueMap(scenario), SE2(), HumanDrive(scenario), options);
  EXPECT_GT(blind.metrics.lateral_mean_all_m, 3.0 * localized.metrics.lateral_mean_all_m);
  EXPECT_GT(blind.metrics.repeat_std_m, 3.0 * localized.metrics.repeat_std_m);
}

TEST(TraceFollowingTest, MapInItsOwnFrameIsHandled) {
  // The same lot, its map rotated and shifted: the follower works in the
  // map frame and the results are measured in the world's.
  const sim::ScenarioConfig scenario = ShortScenario();
  const SE2 T_map_world(20.0, -5.0, 0.3);
  SemanticMap map = TrueMap(scenario);
  for (MapSlot& s : map.slots) {
    for (auto& c : s.corners_map) c = T_map_world * c;
  }
  for (MapTag& t : map.tags) {
    t.p_map = T_map_world * t.p_map;
    t.yaw_map_rad += T_map_world.yaw();
  }
  TraceFollowingOptions options;
  options.runs = 2;
  options.speed_kmh = 10.0;
  const TraceFollowingResult r =
      FollowTrace(scenario, map, T_map_world, HumanDrive(scenario), options);
  EXPECT_TRUE(r.runs[0].finished);
  EXPECT_LT(r.metrics.lateral_mean_all_m, 0.10);
}

// On pixels: the localizer sees only what the front end reads from the
// rendered frames (slots, IDs, tags), and the car still follows the trace.
TEST(TraceFollowingTest, FollowsTheTraceOnPixels) {
  const sim::ScenarioConfig scenario = ShortScenario();
  TraceFollowingOptions options;
  options.runs = 1;
  options.speed_kmh = 10.0;
  options.frames = FromLiveRendering{5.0};
  const TraceFollowingResult live =
      FollowTrace(scenario, TrueMap(scenario), SE2(), HumanDrive(scenario), options);
  ASSERT_TRUE(live.runs[0].finished);
  EXPECT_NEAR(live.runs[0].camera_frames, 5.0 * live.runs[0].duration_s, 10.0);
  EXPECT_LT(live.localization_rmse_m, 0.10);
  EXPECT_LT(live.metrics.lateral_mean_all_m, 0.15);
}

// The speed of the recorded truth (10 Hz) at each sample, by differences.
std::vector<std::pair<double, double>> SpeedsOf(const Trajectory& truth) {
  std::vector<std::pair<double, double>> speeds;
  for (size_t k = 1; k < truth.size(); ++k) {
    const double dt = ToSeconds(truth[k].t_ns - truth[k - 1].t_ns);
    speeds.emplace_back(
        ToSeconds(truth[k].t_ns),
        (truth[k].T_map_vehicle.translation() - truth[k - 1].T_map_vehicle.translation()).norm() /
            dt);
  }
  return speeds;
}

// The first time at or after `from_s` when the car stands (below 0.05 m/s),
// or -1.
double StoppedAt(const Trajectory& truth, double from_s) {
  for (const auto& [t, v] : SpeedsOf(truth)) {
    if (t >= from_s && v < 0.05) return t;
  }
  return -1.0;
}

// Safety in closed loop: the car itself is moved 2.5 m sideways mid-run.
// The localizer sees its landmarks where the map has none, loses track, and
// the supervisor brakes the car to a stop; once relocalized it drives on.
TEST(TraceFollowingTest, AKidnappedCarStopsAndGoesOnWhenRelocalized) {
  const sim::ScenarioConfig scenario = ShortScenario();
  TraceFollowingOptions options;
  options.runs = 1;
  options.speed_kmh = 10.0;
  options.kidnap_at_s = 30.0;
  options.kidnap_offset = Eigen::Vector3d(0.0, 2.5, 0.0);
  options.timeout_factor = 3.0;
  const TraceFollowingResult r =
      FollowTrace(scenario, TrueMap(scenario), SE2(), HumanDrive(scenario), options);
  const TraceRun& run = r.runs.front();
  EXPECT_GE(run.safety_interventions, 1);
  const double stopped_at = StoppedAt(run.truth_world, options.kidnap_at_s);
  ASSERT_GT(stopped_at, 0.0);
  std::printf("kidnap at %.1f s: stopped at %.1f s, %.1f s held, %d interventions, finished %d\n",
              options.kidnap_at_s, stopped_at, run.stopped_s, run.safety_interventions,
              run.finished);
  EXPECT_LT(stopped_at - options.kidnap_at_s, 2.0);
  EXPECT_TRUE(run.finished);
}

// Ten seconds without a camera frame: the estimate goes stale, the car
// stops, and drives on when frames come back.
TEST(TraceFollowingTest, ACameraBlackoutStopsTheCarUntilFramesReturn) {
  const sim::ScenarioConfig scenario = ShortScenario();
  TraceFollowingOptions options;
  options.runs = 1;
  options.speed_kmh = 10.0;
  options.blackout_from_s = 30.0;
  options.blackout_to_s = 40.0;
  const TraceFollowingResult r =
      FollowTrace(scenario, TrueMap(scenario), SE2(), HumanDrive(scenario), options);
  const TraceRun& run = r.runs.front();
  const double stopped_at = StoppedAt(run.truth_world, options.blackout_from_s);
  std::printf("blackout from %.1f s: stopped at %.1f s, %.1f s held, finished %d\n",
              options.blackout_from_s, stopped_at, run.stopped_s, run.finished);
  ASSERT_GT(stopped_at, 0.0);
  EXPECT_LT(stopped_at - options.blackout_from_s, 2.0);
  EXPECT_EQ(run.safety_interventions, 1);
  EXPECT_TRUE(run.finished);
  // Without the supervisor the car drives through the blackout.
  options.safety_stop = false;
  const TraceRun blind =
      FollowTrace(scenario, TrueMap(scenario), SE2(), HumanDrive(scenario), options).runs.front();
  const double blind_stop = StoppedAt(blind.truth_world, options.blackout_from_s);
  EXPECT_TRUE(blind_stop < 0.0 || blind_stop > options.blackout_to_s);
}

// Whether the rear axle's centre stays on the drivable floor: outside every
// slot (where cars park) and 0.9 m (half the car) from walls and pillars.
bool OnDrivableFloor(const sim::World& world, const Eigen::Vector2d& p) {
  for (const sim::WorldSlot& slot : world.slots) {
    int crossings = 0;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d& a = slot.corners_map[k];
      const Eigen::Vector2d& b = slot.corners_map[(k + 1) % 4];
      if ((a.y() > p.y()) != (b.y() > p.y()) &&
          p.x() < a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y())) {
        ++crossings;
      }
    }
    if (crossings % 2 == 1) return false;
  }
  for (const sim::WorldWall& wall : world.walls) {
    const Eigen::Vector2d d = wall.b_map - wall.a_map;
    const double u = std::clamp((p - wall.a_map).dot(d) / d.squaredNorm(), 0.0, 1.0);
    if ((wall.a_map + u * d - p).norm() < 0.9) return false;
  }
  for (const sim::WorldPillar& pillar : world.pillars) {
    if ((pillar.center_map - p).norm() < pillar.half_size_m + 0.9) return false;
  }
  return true;
}

// The safety target: in many closed-loop kidnaps (the car moved up to 1.5 m
// sideways, 3 m along, 0.2 rad) and camera blackouts (5-30 s), the car
// stops within 3 s and stays on the drivable floor. 20 trials each here;
// PARKSLAM_SAFETY_TRIALS=100 for the full measurement (docs/localization.md).
TEST(TraceFollowingTest, SafetyStopsInRandomKidnapsAndBlackouts) {
  const char* env = std::getenv("PARKSLAM_SAFETY_TRIALS");
  const int trials = env != nullptr ? std::max(1, std::atoi(env)) : 20;
  const sim::ScenarioConfig scenario = ShortScenario();
  const sim::World world = sim::BuildWorld(scenario.world);
  const SemanticMap map = TrueMap(scenario);
  const Trajectory trace = HumanDrive(scenario);
  for (const bool kidnap : {true, false}) {
    Random rng(kidnap ? 11 : 12);
    double worst_stop_s = 0.0, sum_stop_s = 0.0;
    int not_stopped = 0, off_floor = 0, finished = 0;
    for (int trial = 0; trial < trials; ++trial) {
      TraceFollowingOptions options;
      options.runs = 1;
      options.speed_kmh = 10.0;
      options.seed = 100 + static_cast<std::uint64_t>(trial);
      options.timeout_factor = 3.0;
      const double fault_s = rng.Uniform(20.0, 70.0);
      if (kidnap) {
        options.kidnap_at_s = fault_s;
        options.kidnap_offset =
            Eigen::Vector3d(rng.Uniform(-3.0, 3.0), rng.Uniform(-1.5, 1.5), rng.Uniform(-0.2, 0.2));
      } else {
        options.blackout_from_s = fault_s;
        options.blackout_to_s = fault_s + rng.Uniform(5.0, 30.0);
      }
      const TraceRun run = FollowTrace(scenario, map, SE2(), trace, options).runs.front();
      const double stopped_at = StoppedAt(run.truth_world, fault_s);
      if (stopped_at < 0.0) {
        ++not_stopped;
      } else {
        worst_stop_s = std::max(worst_stop_s, stopped_at - fault_s);
        sum_stop_s += stopped_at - fault_s;
      }
      // After a kidnap the car is where it was put; judge its driving from there.
      for (const TimedPose& p : run.truth_world) {
        if (ToSeconds(p.t_ns) > fault_s && !OnDrivableFloor(world, p.T_map_vehicle.translation())) {
          ++off_floor;
          break;
        }
      }
      finished += run.finished;
    }
    std::printf(
        "%s: %d trials, stopped in all but %d, mean %.2f s, worst %.2f s after the fault; %d left "
        "the "
        "drivable floor; %d finished the trace\n",
        kidnap ? "closed-loop kidnaps" : "camera blackouts", trials, not_stopped,
        sum_stop_s / std::max(1, trials - not_stopped), worst_stop_s, off_floor, finished);
    EXPECT_EQ(not_stopped, 0);
    // At most 3 s: the bound of a rule that waits for the cameras, derived
    // in docs/localization.md (a landmark 4.4 m away at 2.5 m/s^2: 2.85 s).
    EXPECT_LE(worst_stop_s, 3.0);
    EXPECT_EQ(off_floor, 0);
  }
}

TEST(TraceFollowingTest, InvalidOptionsThrow) {
  const sim::ScenarioConfig scenario = ShortScenario();
  TraceFollowingOptions options;
  options.runs = 0;
  EXPECT_THROW(FollowTrace(scenario, TrueMap(scenario), SE2(), HumanDrive(scenario), options),
               std::invalid_argument);
  options.runs = 1;
  EXPECT_THROW(FollowTrace(scenario, TrueMap(scenario), SE2(), Trajectory{}, options),
               std::invalid_argument);
}

TEST(KidnapTest, RelocalizesInAlmostAllTrials) {
  sim::ScenarioConfig scenario = sim::DefaultScenario();
  const sim::Simulation simulation = sim::Simulate(scenario, 5);
  KidnapOptions options;
  options.trials = 20;
  const KidnapResult r = RunKidnapTrials(
      sim::ToSemanticMap(simulation.world), simulation.log, sim::GroundTruthTrajectory(simulation),
      localization::LocalizerOptions{},
      odometry::EkfOptionsFromSpec(scenario.sensors.odometry, scenario.vehicle), options);
  EXPECT_EQ(r.trials, 20);
  EXPECT_GE(r.successes, 19);
}

}  // namespace
}  // namespace parkslam::harness
