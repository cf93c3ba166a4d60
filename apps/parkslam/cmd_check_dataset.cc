// parkslam check-dataset: what a dataset holds and every problem in it,
// before a long run (docs/dataset_format.md, "Checking a dataset").

#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "commands.h"
#include "parkslam/io/dataset.h"

namespace parkslam::app {

void AddCheckDatasetCommand(CLI::App& app) {
  struct Options {
    std::string dir;
    double max_gap_s = 1.0;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "check-dataset",
      "Check a dataset before a long run: every file read as map and localize read it (headers, "
      "numbers, time order), each stream's rate and longest gap, counts against dataset.yaml, "
      "and each camera image's size against images/rig.yaml. Lists every problem; exits 1 if "
      "there is one");
  cmd->add_option("DIR", options->dir, "Dataset folder")->required();
  cmd->add_option("--max-gap-s", options->max_gap_s,
                  "A stream silent for longer than this is a problem")
      ->check(CLI::Range(0.01, 3600.0))
      ->capture_default_str();
  cmd->add_flag("--json", options->json, "Print one JSON object");
  cmd->callback([options] {
    const io::DatasetCheck check = io::CheckDataset(options->dir, options->max_gap_s);
    if (options->json) {
      nlohmann::json j;
      j["ok"] = check.ok();
      j["errors"] = check.errors;
      j["streams"] = nlohmann::json::array();
      for (const io::StreamSummary& s : check.streams) {
        j["streams"].push_back({{"name", s.name},
                                {"count", s.count},
                                {"first_s", s.first_s},
                                {"last_s", s.last_s},
                                {"median_period_s", s.median_period_s},
                                {"max_gap_s", s.max_gap_s},
                                {"max_gap_after_s", s.max_gap_after_s}});
      }
      std::printf("%s\n", j.dump().c_str());
    } else {
      std::printf("%-34s %8s %10s %10s %9s %9s\n", "stream", "count", "from s", "to s", "rate Hz",
                  "max gap s");
      for (const io::StreamSummary& s : check.streams) {
        std::printf("%-34s %8zu %10.3f %10.3f %9.2f %9.3f\n", s.name.c_str(), s.count, s.first_s,
                    s.last_s, s.median_period_s > 0 ? 1.0 / s.median_period_s : 0.0, s.max_gap_s);
      }
      for (const std::string& e : check.errors) std::printf("problem: %s\n", e.c_str());
      std::printf(
          "%s: %s\n", options->dir.c_str(),
          check.ok() ? "ok" : (std::to_string(check.errors.size()) + " problem(s)").c_str());
    }
    if (!check.ok())
      throw std::runtime_error(options->dir + ": the dataset has problems (listed above)");
  });
}

}  // namespace parkslam::app
