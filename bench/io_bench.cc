// Writing and reading a simulated dataset of the default drive.

#include <benchmark/benchmark.h>

#include <unistd.h>

#include <filesystem>

#include "parkslam/io/dataset.h"
#include "parkslam/sim/simulator.h"

namespace parkslam {
namespace {

io::Dataset DefaultDataset() {
  const sim::ScenarioConfig scenario = sim::DefaultScenario();
  sim::Simulation simulation = sim::Simulate(scenario, 1);
  io::Dataset dataset;
  dataset.name = "bench";
  io::SetScenario(scenario, &dataset);
  dataset.groundtruth_trajectory = sim::GroundTruthTrajectory(simulation);
  dataset.groundtruth_map = sim::ToSemanticMap(simulation.world);
  dataset.log = std::move(simulation.log);
  dataset.slot_labels = std::move(simulation.slot_labels);
  return dataset;
}

std::filesystem::path BenchDir() {
  return std::filesystem::temp_directory_path() /
         ("parkslam_io_bench_" + std::to_string(::getpid()));
}

void BM_WriteDataset(benchmark::State& state) {
  const io::Dataset dataset = DefaultDataset();
  const std::filesystem::path dir = BenchDir();
  for (auto _ : state) io::WriteDataset(dir, dataset);
  std::filesystem::remove_all(dir);
}
BENCHMARK(BM_WriteDataset)->Unit(benchmark::kMillisecond);

void BM_ReadDataset(benchmark::State& state) {
  const std::filesystem::path dir = BenchDir();
  io::WriteDataset(dir, DefaultDataset());
  for (auto _ : state) {
    const io::Dataset read = io::ReadDataset(dir);
    benchmark::DoNotOptimize(read.log.imu_samples.data());
  }
  std::filesystem::remove_all(dir);
}
BENCHMARK(BM_ReadDataset)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace parkslam
