// Mapping and localization under sensor faults (docs/robustness.md,
// "Sensor faults"): each fault of the observation-level stream, 30 s long
// in the middle of the default drive, must leave the map's corner RMSE
// within 1.5x of the fault-free map's and bring localization back within
// 0.10 m of the truth within 5 s of the fault's end; and each must be
// reported by what saw it.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "parkslam/eval/map_metrics.h"
#include "parkslam/harness/dead_reckoning.h"
#include "parkslam/harness/fault_injection.h"
#include "parkslam/harness/sensor_stream.h"
#include "parkslam/localization/localization_run.h"
#include "parkslam/localization/localizer.h"
#include "parkslam/mapping/mapper.h"
#include "parkslam/sim/scenario_config.h"
#include "parkslam/sim/simulator.h"

namespace parkslam::harness {
namespace {

constexpr double kFaultStart_s = 100.0;
constexpr double kFaultDuration_s = 30.0;

struct Drives {
  sim::ScenarioConfig scenario = sim::DefaultScenario();
  sim::Simulation mapping_drive = sim::Simulate(scenario, 1);
  sim::Simulation second_drive = sim::Simulate(scenario, 2);
  SemanticMap truth = sim::ToSemanticMap(mapping_drive.world);
  odometry::OdometryEkfOptions ekf =
      odometry::EkfOptionsFromSpec(scenario.sensors.odometry, scenario.vehicle);
};

const Drives& TheDrives() {
  static const Drives d;
  return d;
}

struct MapRun {
  SemanticMap map;
  eval::MapMetrics metrics;
  odometry::OdometryEkfStats odometry;
  InjectedFaults injected;
};

MapRun MapWith(const std::vector<SensorFault>& faults) {
  const Drives& d = TheDrives();
  SensorStream stream({"mapping drive", 11, &d.mapping_drive.log},
                      {FromObservations{}, {}, faults});
  SensorSource& source = stream.source();
  mapping::Mapper mapper(mapping::MapperOptions{}, d.ekf);
  while (const auto event = source.Next()) mapper.Process(*event);
  mapper.Finish();
  MapRun run;
  run.map = mapper.Map();
  run.metrics = eval::EvaluateMap(run.map, d.truth);
  run.odometry = mapper.odometry_stats();
  if (stream.injected() != nullptr) run.injected = *stream.injected();
  return run;
}

const MapRun& FaultFreeMap() {
  static const MapRun run = MapWith({});
  return run;
}

struct LocalizationRun {
  // The largest position error (m) from 5 s to 30 s after the fault's end.
  double error_after_m = 0.0;
  odometry::OdometryEkfStats odometry;
};

LocalizationRun LocalizeWith(const std::vector<SensorFault>& faults) {
  const Drives& d = TheDrives();
  const MapRun& base = FaultFreeMap();
  const Trajectory truth = sim::GroundTruthTrajectory(d.second_drive);
  SensorStream stream({"second drive", 12, &d.second_drive.log}, {FromObservations{}, {}, faults});
  SensorSource& source = stream.source();
  localization::Localizer localizer(base.map, localization::LocalizerOptions{}, d.ekf);
  const double end_s = kFaultStart_s + kFaultDuration_s;
  LocalizationRun run;
  int checked = 0;
  const localization::LocalizationRun replay = localization::RunLocalization(source, &localizer);
  for (const localization::LocalizationEstimate& e : replay.estimates) {
    const localization::LocalizationEstimate* estimate = &e;
    const double t_s = ToSeconds(estimate->t_ns - truth.front().t_ns);
    if (t_s < end_s + 5.0 || t_s > end_s + 30.0) continue;
    const std::optional<SE2> true_pose = PoseAt(truth, estimate->t_ns);
    if (!true_pose) continue;
    const Eigen::Vector2d estimate_truth_frame =
        base.metrics.T_truth_map * estimate->T_map_vehicle.translation();
    run.error_after_m =
        std::max(run.error_after_m, (estimate_truth_frame - true_pose->translation()).norm());
    ++checked;
  }
  EXPECT_GT(checked, 100);
  run.odometry = localizer.odometry_stats();
  return run;
}

SensorFault Fault(FaultKind kind) {
  SensorFault f;
  f.kind = kind;
  f.start_s = kFaultStart_s;
  f.duration_s = kFaultDuration_s;
  f.magnitude = DefaultMagnitude(kind);
  return f;
}

// Mapping and localization of one fault against the fault-free figures.
void ExpectTolerated(FaultKind kind, MapRun* map_run = nullptr,
                     LocalizationRun* localization_run = nullptr) {
  const MapRun& base = FaultFreeMap();
  const MapRun run = MapWith({Fault(kind)});
  EXPECT_EQ(run.metrics.slots_matched, base.metrics.slots_matched) << ToString(kind);
  EXPECT_LE(run.metrics.slot_corner_rmse_m, 1.5 * base.metrics.slot_corner_rmse_m)
      << ToString(kind) << ": fault-free " << base.metrics.slot_corner_rmse_m << " m";
  const LocalizationRun localization = LocalizeWith({Fault(kind)});
  EXPECT_LT(localization.error_after_m, 0.10) << ToString(kind);
  // The figures of docs/robustness.md.
  std::printf(
      "%-14s corner RMSE %.4f m (fault-free %.4f m), %d of %d slots; localization "
      "error 5-30 s after the fault at most %.3f m\n",
      ToString(kind), run.metrics.slot_corner_rmse_m, base.metrics.slot_corner_rmse_m,
      run.metrics.slots_matched, run.metrics.slots_true, localization.error_after_m);
  if (map_run != nullptr) *map_run = run;
  if (localization_run != nullptr) *localization_run = localization;
}

TEST(FaultToleranceTest, FaultFreeBaseline) {
  const MapRun& base = FaultFreeMap();
  // 141 slots in the lot; one is never passed closely enough to be seen.
  EXPECT_EQ(base.metrics.slots_true, 141);
  EXPECT_EQ(base.metrics.slots_matched, 140);
  EXPECT_LT(base.metrics.slot_corner_rmse_m, 0.06);
  EXPECT_LT(LocalizeWith({}).error_after_m, 0.10);
}

TEST(FaultToleranceTest, CameraGapOf30Seconds) {
  MapRun run;
  ExpectTolerated(FaultKind::kCameraGap, &run);
  EXPECT_EQ(run.injected.frames_dropped, 600);  // 30 s of slot and tag frames at 10 Hz
}

TEST(FaultToleranceTest, LateFramesAreDroppedAndCounted) {
  MapRun run;
  LocalizationRun localization;
  ExpectTolerated(FaultKind::kLateFrames, &run, &localization);
  EXPECT_EQ(run.injected.frames_delayed, 600);
  EXPECT_EQ(run.odometry.late_events, 600);
  EXPECT_EQ(localization.odometry.late_events, 600);
}

TEST(FaultToleranceTest, ImuSpikesAreGatedOut) {
  MapRun run;
  ExpectTolerated(FaultKind::kImuSpikes, &run);
  EXPECT_EQ(run.injected.imu_spikes, 60);
  EXPECT_GE(run.odometry.rejected[odometry::OdometryEkfStats::kGyro], 60);
  EXPECT_GE(run.odometry.rejected[odometry::OdometryEkfStats::kHeading], 60);
}

TEST(FaultToleranceTest, HeadingJumpIsTakenAsANewOffset) {
  MapRun run;
  ExpectTolerated(FaultKind::kHeadingJump, &run);
  // In at the start of the window, out at its end.
  EXPECT_EQ(run.odometry.resets[odometry::OdometryEkfStats::kHeading], 2);
}

TEST(FaultToleranceTest, WheelSpeedDropout) {
  MapRun run;
  ExpectTolerated(FaultKind::kWheelDropout, &run);
  EXPECT_NEAR(run.odometry.longest_gap_s[odometry::OdometryEkfStats::kWheelSpeed], kFaultDuration_s,
              0.05);
}

TEST(FaultToleranceTest, ClockJitter) {
  MapRun run;
  ExpectTolerated(FaultKind::kClockJitter, &run);
  EXPECT_GT(run.injected.events_jittered, 6000);
  EXPECT_GT(run.odometry.late_events, 1000);  // out of order after the jitter: dropped
}

}  // namespace
}  // namespace parkslam::harness
