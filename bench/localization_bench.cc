// One localization update on the default lot: the localizer's work at one
// camera frame (prediction, association, gated updates). Goal: at most 1 ms.

#include <benchmark/benchmark.h>

#include "parkslam/harness/dead_reckoning.h"
#include "parkslam/localization/localizer.h"
#include "parkslam/sim/simulator.h"

namespace parkslam {
namespace {

void BM_LocalizationUpdate(benchmark::State& state) {
  sim::ScenarioConfig scenario = sim::DefaultScenario();
  scenario.sensors.ids.confusion_rate = 0.15;
  scenario.sensors.ids.partial_rate = 0.10;
  const sim::Simulation simulation = sim::Simulate(scenario, 2);
  const SemanticMap map = sim::ToSemanticMap(simulation.world);
  const auto odometry = odometry::EkfOptionsFromSpec(scenario.sensors.odometry, scenario.vehicle);
  // Time only the camera frames (the odometry samples between them are fed
  // untimed), each frame's full localizer work.
  std::vector<SensorEvent> events;
  SensorLogSource source(simulation.log);
  while (const auto e = source.Next()) events.push_back(*e);
  size_t frames = 0, slots = 0;
  for (auto _ : state) {
    state.PauseTiming();
    localization::Localizer localizer(map, {}, odometry);
    localizer.SetPose(simulation.states.front().T_map_vehicle,
                      Eigen::Vector3d(0.01, 0.01, 0.001).asDiagonal());
    state.ResumeTiming();
    for (const SensorEvent& e : events) {
      const bool frame = std::holds_alternative<SlotObservationFrame>(e) ||
                         std::holds_alternative<TagObservationFrame>(e);
      if (!frame) {
        state.PauseTiming();
        localizer.Process(e);
        state.ResumeTiming();
        continue;
      }
      benchmark::DoNotOptimize(localizer.Process(e));
      ++frames;
      if (const auto* f = std::get_if<SlotObservationFrame>(&e)) slots += f->slots.size();
    }
  }
  state.SetItemsProcessed(static_cast<int64_t>(frames));
  state.counters["us_per_frame"] = benchmark::Counter(
      static_cast<double>(frames), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["slots_per_slot_frame"] = static_cast<double>(slots) / (frames / 2.0);
}
BENCHMARK(BM_LocalizationUpdate)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
}  // namespace parkslam
