// The corner sigmas a map states against the errors it has, on a drive
// whose map is held by slots alone: the default lot with its tags removed
// (observation level, seed 1). Between loop closures the dead reckoning
// drifts, so a corner far from the last closure is less sure than one next
// to it; the graph's marginal covariances say so, a sigma from the number
// of sightings cannot.

#include <gtest/gtest.h>

#include <iostream>
#include <string>

#include "parkslam/eval/map_metrics.h"
#include "parkslam/mapping/mapper.h"
#include "parkslam/odometry/odometry_ekf.h"
#include "parkslam/sensor/sensor_log.h"
#include "parkslam/sim/simulator.h"

namespace parkslam {
namespace {

eval::MapMetrics MapWithoutTags(bool sigma_from_graph) {
  sim::ScenarioConfig scenario = sim::DefaultScenario();
  scenario.world.tag_count = 0;
  const sim::Simulation drive = sim::Simulate(scenario, 1);
  mapping::MapperOptions options;
  options.corner_sigma_from_graph = sigma_from_graph;
  mapping::Mapper mapper(options,
                         odometry::EkfOptionsFromSpec(scenario.sensors.odometry, scenario.vehicle));
  SensorLogSource source(drive.log);
  while (const auto event = source.Next()) mapper.Process(*event);
  mapper.Finish();
  return eval::EvaluateMap(mapper.Map(), sim::ToSemanticMap(drive.world));
}

TEST(MapUncertaintyTest, GraphSigmasHoldTheSeenCornersErrorsWithoutTags) {
  const eval::MapMetrics graph = MapWithoutTags(true);
  ASSERT_GT(graph.observed_corners.count, 200);
  // Measured 0.041 m RMSE, 98.2 % inside 2 sigma (the chi-square band of
  // 95.45 %); from the sightings' count 70.4 %.
  EXPECT_LT(graph.observed_corners.rmse_m, 0.05);
  EXPECT_GT(graph.observed_corners.within_2sigma, 0.9);
  EXPECT_LE(graph.observed_corners.within_2sigma, 0.995);
  const eval::MapMetrics counted = MapWithoutTags(false);
  EXPECT_LT(counted.observed_corners.within_2sigma, 0.8);
}

// A wheel that reads 0.6 % fast on the same lot (the simulator's own draw
// of the scale error held at none): the dead reckoning learns some of it in
// turns, the rest stretches the map between loop closures while the graph,
// taking every odometry increment's error as independent, states the
// corners as sure as ever. With the scale error one unknown of the graph
// (MapperOptions::estimate_wheel_scale) the map finds it and keeps its
// corners and its sigmas.
struct ScaledMap {
  eval::MapMetrics metrics;
  double wheel_scale_error = 0.0;  // the map's estimate, 0 without one
};

ScaledMap MapWithFastWheel(bool estimate_wheel_scale) {
  sim::ScenarioConfig scenario = sim::DefaultScenario();
  scenario.world.tag_count = 0;
  scenario.sensors.odometry.wheel_speed_scale_sigma = 0.0;
  sim::Simulation drive = sim::Simulate(scenario, 1);
  for (WheelSpeed& w : drive.log.wheel_speeds) w.speed_mps *= 1.006;
  odometry::OdometryEkfOptions ekf =
      odometry::EkfOptionsFromSpec(scenario.sensors.odometry, scenario.vehicle);
  ekf.wheel_scale_sigma = 0.003;  // the car's datasheet
  mapping::MapperOptions options;
  options.estimate_wheel_scale = estimate_wheel_scale;
  mapping::Mapper mapper(options, ekf);
  SensorLogSource source(drive.log);
  while (const auto event = source.Next()) mapper.Process(*event);
  mapper.Finish();
  const SemanticMap map = mapper.Map();
  ScaledMap out;
  out.metrics = eval::EvaluateMap(map, sim::ToSemanticMap(drive.world));
  if (const auto it = map.metadata.find("wheel_scale_error"); it != map.metadata.end()) {
    out.wheel_scale_error = std::stod(it->second);
  }
  return out;
}

TEST(MapUncertaintyTest, AWheelThatReadsFastIsFoundByTheGraph) {
  const ScaledMap with = MapWithFastWheel(true);
  const ScaledMap without = MapWithFastWheel(false);
  std::cout << "with the estimate: " << with.wheel_scale_error << ", "
            << with.metrics.observed_corners.rmse_m << " m, "
            << with.metrics.observed_corners.within_2sigma
            << " inside; without: " << without.metrics.observed_corners.rmse_m << " m, "
            << without.metrics.observed_corners.within_2sigma << "\n";
  // Measured: found 0.0062; 0.022 m, 99.6 % inside 2 sigma; without the
  // estimate 0.042 m, 78.6 %. (Before the dead reckoning carried the car's
  // acceleration: 0.032 m, 94.3 %; 0.048 m, 82.1 %.) The map is now better
  // than its sigmas on this lot without tags, above the 98 % of a
  // calibrated sigma (docs/results/hard_worlds.md).
  EXPECT_NEAR(with.wheel_scale_error, 0.006, 0.001);
  EXPECT_LT(with.metrics.observed_corners.rmse_m, 0.03);
  EXPECT_GE(with.metrics.observed_corners.within_2sigma, 0.9);
  EXPECT_EQ(without.wheel_scale_error, 0.0);
  EXPECT_GT(without.metrics.observed_corners.rmse_m, with.metrics.observed_corners.rmse_m + 0.015);
  EXPECT_LT(without.metrics.observed_corners.within_2sigma, 0.85);
}

}  // namespace
}  // namespace parkslam
