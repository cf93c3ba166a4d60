// Observation-level simulation and Kalman dead reckoning on the default lot.
// The goal: a 10-minute drive simulated in under 10 s.

#include <benchmark/benchmark.h>

#include "parkslam/harness/dead_reckoning.h"
#include "parkslam/sim/simulator.h"

namespace parkslam {
namespace {

// Five laps make the default drive about ten and a half minutes long.
sim::ScenarioConfig TenMinuteDrive() {
  sim::ScenarioConfig scenario = sim::DefaultScenario();
  scenario.route.laps = 5;
  return scenario;
}

void BM_SimulateTenMinuteDrive(benchmark::State& state) {
  const sim::ScenarioConfig scenario = TenMinuteDrive();
  double duration_s = 0.0;
  for (auto _ : state) {
    const sim::Simulation sim = sim::Simulate(scenario, 1);
    duration_s = ToSeconds(sim.states.back().t_ns - sim.states.front().t_ns);
    benchmark::DoNotOptimize(sim.log.imu_samples.data());
  }
  state.counters["drive_s"] = duration_s;
}
BENCHMARK(BM_SimulateTenMinuteDrive)->Unit(benchmark::kMillisecond);

void BM_DeadReckoningTenMinuteDrive(benchmark::State& state) {
  const sim::ScenarioConfig scenario = TenMinuteDrive();
  const sim::Simulation sim = sim::Simulate(scenario, 1);
  const auto options = odometry::EkfOptionsFromSpec(scenario.sensors.odometry, scenario.vehicle);
  for (auto _ : state) {
    SensorLogSource source(sim.log);
    const auto result = harness::RunDeadReckoning(source, options, {});
    benchmark::DoNotOptimize(result.poses.data());
  }
  state.counters["events"] = static_cast<double>(
      sim.log.wheel_speeds.size() + sim.log.steering_angles.size() + sim.log.imu_samples.size());
}
BENCHMARK(BM_DeadReckoningTenMinuteDrive)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace parkslam
