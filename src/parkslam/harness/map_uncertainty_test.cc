// The corner sigmas a map states against the errors it has, on a drive
// whose map is held by slots alone: the default lot with its tags removed
// (observation level, seed 1). Between loop closures the dead reckoning
// drifts, so a corner far from the last closure is less sure than one next
// to it; the graph's marginal covariances say so, a sigma from the number
// of sightings cannot.

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace parkslam
