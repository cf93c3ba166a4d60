#include <cstdio>
#include <filesystem>
#include <iostream>

#include "commands.h"
#include "parkslam/eval/map_metrics.h"
#include "parkslam/io/dataset.h"
#include "parkslam/io/map_json.h"
#include "steps.h"

namespace parkslam::app {

void AddEvalMapCommand(CLI::App& app) {
  struct Options {
    std::string map, truth, dataset;
    bool json = false;
    int min_sightings = 3;
  };
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "eval-map",
      "Compare a map with the ground truth: slot corner RMSE after SE(2) alignment; true, "
      "matched, missed, spurious and duplicate slots; ID accuracy; temporary IDs; tags");
  cmd->add_option("--map", options->map, "Map JSON to evaluate")->required();
  cmd->add_option("--truth", options->truth, "Ground-truth map JSON")->required();
  cmd->add_option("--dataset", options->dataset,
                  "Dataset whose slot labels say which slots the car passed (only those "
                  "count); by default the dataset holding --truth, when there is one");
  cmd->add_option("--min-sightings", options->min_sightings,
                  "Detections of a slot for it to count as passed")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  cmd->add_flag("--json", options->json, "Print one JSON object");
  cmd->callback([options] {
    const SemanticMap map = io::ReadMap(options->map);
    const SemanticMap truth = io::ReadMap(options->truth);
    eval::MapMetricsOptions metrics_options;
    std::filesystem::path dataset_dir = options->dataset;
    if (dataset_dir.empty()) {
      // DIR/groundtruth/map.json: use DIR when it is a dataset.
      const auto candidate = std::filesystem::path(options->truth).parent_path().parent_path();
      if (std::filesystem::exists(candidate / "dataset.yaml")) dataset_dir = candidate;
    }
    if (!dataset_dir.empty()) {
      metrics_options.truth_slot_mask =
          PassedSlots(io::ReadDataset(dataset_dir), truth.slots.size(), options->min_sightings);
    }
    const eval::MapMetrics m = eval::EvaluateMap(map, truth, metrics_options);
    if (options->json) {
      std::cout << MapMetricsToJson(m).dump() << "\n";
      return;
    }
    std::printf("%s\n", DescribeMapMetrics(m).c_str());
  });
}

}  // namespace parkslam::app
