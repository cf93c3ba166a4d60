// Long drives (docs/robustness.md, "Soak"): the windowed solve of the
// mapper must not grow with the number of times the car comes back, and
// bounding it must not change the final map.

#include <gtest/gtest.h>

#include <cstdio>

#include "parkslam/eval/map_metrics.h"
#include "parkslam/mapping/mapper.h"
#include "parkslam/pipeline/dead_reckoning.h"
#include "parkslam/sim/scenario_config.h"
#include "parkslam/sim/simulator.h"

namespace parkslam::pipeline {
namespace {

struct Result {
  mapping::MapperStats stats;
  eval::MapMetrics metrics;
};

Result MapLaps(int laps, int history) {
  sim::ScenarioConfig scenario = sim::DefaultScenario();
  scenario.route.laps = laps;
  const sim::Simulation drive = sim::Simulate(scenario, 3);
  mapping::MapperOptions options;
  options.window_history_observations = history;
  mapping::Mapper mapper(options,
                         EkfOptionsFromSensorSpec(scenario.sensors.odometry, scenario.vehicle));
  SensorLogSource source(drive.log);
  while (const auto event = source.Next()) mapper.Process(*event);
  mapper.Finish();
  return {mapper.stats(), eval::EvaluateMap(mapper.Map(), sim::ToSemanticMap(drive.world))};
}

TEST(SoakTest, WindowedSolveStaysBoundedOverLapsAndTheMapIsTheSame) {
  const mapping::MapperOptions defaults;
  const Result two = MapLaps(2, defaults.window_history_observations);
  const Result eight = MapLaps(8, defaults.window_history_observations);
  const Result eight_all = MapLaps(8, 0);  // every older observation enters
  // Bounded: eight laps need hardly larger windowed solves than two...
  EXPECT_LT(eight.stats.max_window_residual_blocks,
            1.25 * two.stats.max_window_residual_blocks);
  // ...where taking the whole history makes them grow with the laps.
  EXPECT_GT(eight_all.stats.max_window_residual_blocks,
            2.0 * eight.stats.max_window_residual_blocks);
  // The final solve takes everything: the same map either way.
  EXPECT_EQ(eight.metrics.slots_matched, eight_all.metrics.slots_matched);
  EXPECT_NEAR(eight.metrics.slot_corner_rmse_m, eight_all.metrics.slot_corner_rmse_m, 0.002);
  EXPECT_NEAR(eight.metrics.id_accuracy, eight_all.metrics.id_accuracy, 0.01);
  std::printf("windowed solve, most residual blocks: 2 laps %d, 8 laps %d (whole history: %d); "
              "8 laps corner RMSE %.4f m (whole history %.4f m)\n",
              two.stats.max_window_residual_blocks, eight.stats.max_window_residual_blocks,
              eight_all.stats.max_window_residual_blocks, eight.metrics.slot_corner_rmse_m,
              eight_all.metrics.slot_corner_rmse_m);
}

}  // namespace
}  // namespace parkslam::pipeline
