// Long drives (docs/robustness.md, "Soak"): the windowed solve of the
// mapper must not grow with the number of times the car comes back, and
// bounding it must not change the final map.

#include <gtest/gtest.h>

#include <cstdio>

#include "parkslam/eval/map_metrics.h"
#include "parkslam/harness/dead_reckoning.h"
#include "parkslam/mapping/mapper.h"
#include "parkslam/sim/scenario_config.h"
#include "parkslam/sim/simulator.h"

namespace parkslam::harness {
namespace {

struct Result {
  mapping::MapperStats stats;
  eval::MapMetrics metrics;
  size_t records_stored = 0;
  size_t keyframes_stored = 0;
};

Result MapLaps(int laps, int history,
               int records_per_landmark = mapping::MapperOptions().max_records_per_landmark,
               int retire_check_min_records = mapping::MapperOptions().retire_check_min_records) {
  sim::ScenarioConfig scenario = sim::DefaultScenario();
  scenario.route.laps = laps;
  const sim::Simulation drive = sim::Simulate(scenario, 3);
  mapping::MapperOptions options;
  options.window_history_observations = history;
  options.max_records_per_landmark = records_per_landmark;
  options.retire_check_min_records = retire_check_min_records;
  mapping::Mapper mapper(options,
                         odometry::EkfOptionsFromSpec(scenario.sensors.odometry, scenario.vehicle));
  SensorLogSource source(drive.log);
  while (const auto event = source.Next()) mapper.Process(*event);
  const size_t stored = mapper.slot_records().size() + mapper.tag_records().size();
  const size_t keyframes = mapper.keyframes().size();
  mapper.Finish();
  return {mapper.stats(), eval::EvaluateMap(mapper.Map(), sim::ToSemanticMap(drive.world)), stored,
          keyframes};
}

TEST(SoakTest, WindowedSolveStaysBoundedOverLapsAndTheMapIsTheSame) {
  const mapping::MapperOptions defaults;
  const Result two = MapLaps(2, defaults.window_history_observations);
  const Result eight = MapLaps(8, defaults.window_history_observations);
  const Result eight_all = MapLaps(8, 0);  // every older observation enters
  // Bounded: eight laps need hardly larger windowed solves than two...
  EXPECT_LT(eight.stats.max_window_residual_blocks, 1.25 * two.stats.max_window_residual_blocks);
  // ...where taking the whole history makes them grow with the laps.
  EXPECT_GT(eight_all.stats.max_window_residual_blocks,
            2.0 * eight.stats.max_window_residual_blocks);
  // The final solve takes everything: the same map either way.
  EXPECT_EQ(eight.metrics.slots_matched, eight_all.metrics.slots_matched);
  EXPECT_NEAR(eight.metrics.slot_corner_rmse_m, eight_all.metrics.slot_corner_rmse_m, 0.002);
  EXPECT_NEAR(eight.metrics.id_accuracy, eight_all.metrics.id_accuracy, 0.01);
  std::printf(
      "windowed solve, most residual blocks: 2 laps %d, 8 laps %d (whole history: %d); "
      "8 laps corner RMSE %.4f m (whole history %.4f m)\n",
      two.stats.max_window_residual_blocks, eight.stats.max_window_residual_blocks,
      eight_all.stats.max_window_residual_blocks, eight.metrics.slot_corner_rmse_m,
      eight_all.metrics.slot_corner_rmse_m);
}

TEST(SoakTest, RetiredRecordsBoundTheStorageAndKeepTheMap) {
  // The default cap, looked at early (2,000 records instead of 16,384) so
  // that eight laps reach it: each landmark over 200 records is thinned,
  // the retired records' votes kept, and the keyframes no record names
  // culled; false detections' slots pruned. Measured: 22,949 of 36,906
  // records and 9,142 of 10,299 keyframes stored, corner RMSE 0.0344 m
  // against 0.0330 m with every record.
  const Result all = MapLaps(8, mapping::MapperOptions().window_history_observations, 0);
  const Result capped = MapLaps(8, mapping::MapperOptions().window_history_observations, 200, 2000);
  EXPECT_GT(capped.stats.records_retired, 0);
  EXPECT_GT(capped.stats.slots_pruned, 0);
  EXPECT_EQ(all.stats.records_retired, 0);
  // The storage after the drive is what the map needs, not what the drive saw.
  EXPECT_LT(capped.records_stored, 0.7 * all.records_stored);
  // Keyframes that no kept record names are folded into their successors.
  EXPECT_GT(capped.stats.keyframes_culled, 0);
  EXPECT_EQ(capped.keyframes_stored + static_cast<size_t>(capped.stats.keyframes_culled),
            static_cast<size_t>(capped.stats.keyframes));
  EXPECT_EQ(capped.metrics.slots_matched, all.metrics.slots_matched);
  EXPECT_EQ(capped.metrics.slots_spurious, all.metrics.slots_spurious);
  EXPECT_NEAR(capped.metrics.slot_corner_rmse_m, all.metrics.slot_corner_rmse_m, 0.003);
  EXPECT_NEAR(capped.metrics.id_accuracy, all.metrics.id_accuracy, 0.01);
  std::printf(
      "8 laps: %zu records stored, %d retired (every record kept: %zu); %zu of %d keyframes "
      "stored; corner RMSE %.4f m (every record: %.4f m), ID accuracy %.3f (%.3f)\n",
      capped.records_stored, capped.stats.records_retired, all.records_stored,
      capped.keyframes_stored, capped.stats.keyframes, capped.metrics.slot_corner_rmse_m,
      all.metrics.slot_corner_rmse_m, capped.metrics.id_accuracy, all.metrics.id_accuracy);
}

}  // namespace
}  // namespace parkslam::harness
