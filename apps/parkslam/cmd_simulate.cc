#include <chrono>
#include <cstdio>
#include <iostream>

#include "commands.h"
#include "parkslam/io/dataset.h"
#include "parkslam/io/scenario_yaml.h"
#include "steps.h"

namespace parkslam::app {

void AddSimulateCommand(CLI::App& app) {
  struct Options {
    ScenarioOptions scenario;
    std::uint64_t seed = 1;
    std::string out;
    bool dump_config = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "simulate",
      "Simulate a drive through a parking lot and write it as a dataset with ground truth");
  AddScenarioOptions(cmd, &options->scenario);
  cmd->add_option("--seed", options->seed, "Random seed (same seed, same data)")
      ->capture_default_str();
  cmd->add_option("--out", options->out, "Dataset folder to write");
  cmd->add_flag("--dump-config", options->dump_config,
                "Print the resolved scenario as YAML and exit (a start for your own world)");
  cmd->callback([options] {
    const sim::ScenarioConfig scenario = ResolveScenario(options->scenario);
    if (options->dump_config) {
      std::cout << io::ScenarioToYaml(scenario);
      return;
    }
    if (options->out.empty()) throw CLI::RequiredError("--out");
    const auto start = std::chrono::steady_clock::now();
    const io::Dataset dataset = SimulateDataset(scenario, options->seed);
    const auto simulated = std::chrono::steady_clock::now();
    io::WriteDataset(options->out, dataset);
    const auto written = std::chrono::steady_clock::now();
    std::printf("%s\n", DescribeDataset(dataset).c_str());
    std::printf("simulated in %.2f s, written to %s in %.2f s\n",
                std::chrono::duration<double>(simulated - start).count(), options->out.c_str(),
                std::chrono::duration<double>(written - simulated).count());
  });
}

}  // namespace parkslam::app
