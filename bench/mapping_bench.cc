// The mapper on the default drive (seed 1, 15 % confused and 10 % partial
// IDs): the final batch optimization, and the per-keyframe online update.
// Goals: batch solve at most 2 s, online update at most 20 ms per keyframe.

#include <benchmark/benchmark.h>

#include <algorithm>

#include "parkslam/harness/dead_reckoning.h"
#include "parkslam/mapping/mapper.h"
#include "parkslam/sim/simulator.h"

namespace parkslam {
namespace {

struct Drive {
  sim::ScenarioConfig scenario;
  sim::Simulation simulation;
};

const Drive& DefaultDrive() {
  static const Drive drive = [] {
    Drive d;
    d.scenario = sim::DefaultScenario();
    d.scenario.sensors.ids.confusion_rate = 0.15;
    d.scenario.sensors.ids.partial_rate = 0.10;
    d.simulation = sim::Simulate(d.scenario, 1);
    return d;
  }();
  return drive;
}

mapping::Mapper FeedAll(mapping::MappingMode mode, mapping::TrustRegion region, double radius) {
  const Drive& d = DefaultDrive();
  mapping::MapperOptions options;
  options.mode = mode;
  options.trust_region = region;
  options.initial_trust_region_radius = radius;
  mapping::Mapper mapper(
      options, odometry::EkfOptionsFromSpec(d.scenario.sensors.odometry, d.scenario.vehicle),
      d.simulation.states.front().T_map_vehicle);
  SensorLogSource source(d.simulation.log);
  while (const auto event = source.Next()) mapper.Process(*event);
  return mapper;
}

// The full optimization at the end of a batch session (Finish: final solves,
// duplicate merging, ID assignment). The front-end pass is not timed.
void BM_MappingBatchFinish(benchmark::State& state) {
  const auto region = state.range(0) == 0 ? mapping::TrustRegion::kLevenbergMarquardt
                                          : mapping::TrustRegion::kDogleg;
  const double radius = static_cast<double>(state.range(1));
  int iterations = 0;
  for (auto _ : state) {
    state.PauseTiming();
    mapping::Mapper mapper = FeedAll(mapping::MappingMode::kBatch, region, radius);
    state.ResumeTiming();
    mapper.Finish();
    iterations = mapper.stats().final_iterations;
  }
  state.counters["solver_iterations"] = iterations;
}
BENCHMARK(BM_MappingBatchFinish)
    ->ArgNames({"dogleg", "radius"})
    ->Args({0, 10000})
    ->Args({0, 100000000})
    ->Args({1, 10000})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

// One online session; the counters give the per-keyframe update times.
void BM_MappingOnlineKeyframeUpdate(benchmark::State& state) {
  std::vector<double> ms;
  for (auto _ : state) {
    mapping::Mapper mapper =
        FeedAll(mapping::MappingMode::kOnline, mapping::TrustRegion::kLevenbergMarquardt, 1e4);
    ms = mapper.stats().keyframe_update_ms;
  }
  std::sort(ms.begin(), ms.end());
  state.counters["keyframes"] = static_cast<double>(ms.size());
  state.counters["update_median_ms"] = ms[ms.size() / 2];
  state.counters["update_p99_ms"] = ms[ms.size() * 99 / 100];
  state.counters["update_max_ms"] = ms.back();
}
BENCHMARK(BM_MappingOnlineKeyframeUpdate)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
}  // namespace parkslam
