#include "parkslam/pipeline/trace_following.h"

#include <gtest/gtest.h>

#include "parkslam/pipeline/dead_reckoning.h"
#include "parkslam/pipeline/kidnap.h"
#include "parkslam/sim/route.h"
#include "parkslam/sim/simulator.h"

namespace parkslam::pipeline {
namespace {

// The default lot with a short drive: the corridor, aisle 1, up the east
// cross aisle and back west through aisle 3 (no laps).
sim::ScenarioConfig ShortDrive() {
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
  return sim::ToSemanticMap(sim::BuildWorld(scenario.world, scenario.world.seed));
}

TEST(TraceFollowingTest, LocalizedRunsRepeatTheTraceClosely) {
  const sim::ScenarioConfig scenario = ShortDrive();
  TraceFollowingOptions options;
  options.runs = 3;
  options.speed_kmh = 10.0;
  const TraceFollowingResult r =
      FollowTrace(scenario, TrueMap(scenario), SE2(), HumanDrive(scenario), options);
  ASSERT_EQ(r.runs.size(), 3u);
  for (const TraceRun& run : r.runs) {
    EXPECT_TRUE(run.finished);
    EXPECT_EQ(run.lost_frames, 0);
  }
  EXPECT_LT(r.metrics.repeat_std_m, 0.05);
  EXPECT_LT(r.metrics.lateral_mean_all_m, 0.10);
  EXPECT_LT(r.localization_rmse_m, 0.10);
}

TEST(TraceFollowingTest, DeadReckoningAloneDriftsAway) {
  const sim::ScenarioConfig scenario = ShortDrive();
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
  const sim::ScenarioConfig scenario = ShortDrive();
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
  const TraceFollowingResult r = FollowTrace(scenario, map, T_map_world, HumanDrive(scenario), options);
  EXPECT_TRUE(r.runs[0].finished);
  EXPECT_LT(r.metrics.lateral_mean_all_m, 0.10);
}

// On pixels: the localizer sees only what the front end reads from the
// rendered frames (slots, IDs, tags), and the car still follows the trace.
TEST(TraceFollowingTest, FollowsTheTraceOnPixels) {
  const sim::ScenarioConfig scenario = ShortDrive();
  TraceFollowingOptions options;
  options.runs = 1;
  options.speed_kmh = 10.0;
  options.live_image_rate_hz = 5.0;
  const TraceFollowingResult live =
      FollowTrace(scenario, TrueMap(scenario), SE2(), HumanDrive(scenario), options);
  ASSERT_TRUE(live.runs[0].finished);
  EXPECT_NEAR(live.runs[0].camera_frames, 5.0 * live.runs[0].duration_s, 10.0);
  EXPECT_LT(live.localization_rmse_m, 0.10);
  EXPECT_LT(live.metrics.lateral_mean_all_m, 0.15);
}

TEST(TraceFollowingTest, InvalidOptionsThrow) {
  const sim::ScenarioConfig scenario = ShortDrive();
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
      EkfOptionsFromSensorSpec(scenario.sensors.odometry, scenario.vehicle), options);
  EXPECT_EQ(r.trials, 20);
  EXPECT_GE(r.successes, 19);
}

}  // namespace
}  // namespace parkslam::pipeline
