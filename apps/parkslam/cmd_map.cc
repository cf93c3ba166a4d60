#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "parkslam/harness/dead_reckoning.h"
#include "parkslam/io/dataset.h"
#include "parkslam/io/map_json.h"
#include "parkslam/io/output_guard.h"
#include "parkslam/io/tum.h"
#include "progress.h"
#include "steps.h"

namespace parkslam::app {

namespace map_command {

struct Options {
  std::string dataset, out, trajectory_out, robust = "maxmix", mode = "batch", init, solver = "lm";
  double initial_trust_region = 1e8;
  PixelOptions pixels;
  ConfigOptions config;
};

// The mapper's options from --config with the command's choices over them;
// the initial trust region only where given.
mapping::MapperOptions MapperOptionsOf(const Options& o, const AlgorithmOptions& config,
                                       bool initial_trust_region_given) {
  mapping::MapperOptions mapper_options = config.mapper;
  mapper_options.robust =
      o.robust == "none" ? mapping::RobustMode::kNone : mapping::RobustMode::kMaxMixture;
  mapper_options.mode =
      o.mode == "online" ? mapping::MappingMode::kOnline : mapping::MappingMode::kBatch;
  mapper_options.trust_region = o.solver == "dogleg" ? mapping::TrustRegion::kDogleg
                                                     : mapping::TrustRegion::kLevenbergMarquardt;
  if (initial_trust_region_given) {
    mapper_options.initial_trust_region_radius = o.initial_trust_region;
  }
  return mapper_options;
}

void Run(const Options& o, bool initial_trust_region_given) {
  io::CheckOutputsSpareInputs({{o.out, "--out"}, {o.trajectory_out, "--trajectory-out"}},
                              {{o.dataset, "DIR"}});
  const AlgorithmOptions config = o.config.Load();
  const io::Dataset dataset = io::ReadDataset(o.dataset);
  const mapping::MapperOptions mapper_options =
      MapperOptionsOf(o, config, initial_trust_region_given);
  std::optional<SE2> init;
  if (!o.init.empty()) init = ParsePose(o.init, "--init");
  const auto start = std::chrono::steady_clock::now();
  std::string faults_seen;
  mapping::Mapper mapper = BuildMap(dataset, mapper_options, init, true,
                                    o.pixels.Stream(o.dataset, config.front_end), &faults_seen);
  const double total_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  io::WriteMap(o.out, mapper.Map());
  if (!o.trajectory_out.empty()) {
    io::WriteTum(o.trajectory_out, mapper.KeyframeTrajectory());
  }
  std::printf("%s\n", DescribeMapping(mapper, total_s).c_str());
  if (!faults_seen.empty()) std::printf("%s\n", faults_seen.c_str());
  std::printf("map written to %s\n", o.out.c_str());
}

}  // namespace map_command

void AddMapCommand(CLI::App& app) {
  using namespace map_command;
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "map",
      "Build the semantic map (slots with IDs, tags) of a dataset: association by ID and "
      "nearest neighbour, a factor graph with rectangular slot constraints and a Max-Mixture "
      "back-end");
  cmd->add_option("DIR", options->dataset, "Dataset folder")->required();
  cmd->add_option("--out", options->out, "Map JSON to write")->required();
  cmd->add_option("--trajectory-out", options->trajectory_out,
                  "TUM file for the optimized keyframe trajectory");
  cmd->add_option("--robust", options->robust,
                  "maxmix: Max-Mixture back-end; none: the plain Gaussian graph (the paper's "
                  "baseline)")
      ->check(CLI::IsMember({"maxmix", "none"}))
      ->capture_default_str();
  cmd->add_option("--mode", options->mode,
                  "online: a bounded windowed update per keyframe; batch: a full optimization "
                  "at the end")
      ->check(CLI::IsMember({"online", "batch"}))
      ->capture_default_str();
  cmd->add_option("--solver", options->solver, "Trust region of the final solve: lm or dogleg")
      ->check(CLI::IsMember({"lm", "dogleg"}))
      ->capture_default_str();
  cmd->add_option("--initial-trust-region", options->initial_trust_region,
                  "Initial trust-region radius of the final solve")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            double v = 0.0;
            if (!CLI::detail::lexical_cast(text, v) || !(v >= 1e-32 && v <= 1e16)) {
              return "must be a number from 1e-32 to 1e16 (the solver's own bounds), got " + text;
            }
            return "";
          },
          "1e-32..1e16"))
      ->capture_default_str();
  AddPixelOptions(cmd, &options->pixels);
  AddConfigOptions(cmd, &options->config);
  cmd->add_option("--init", options->init,
                  "Known start pose x,y,yaw in the map frame (metres, radians); without it the "
                  "map frame starts at the first pose");
  cmd->callback([options, cmd] { Run(*options, cmd->count("--initial-trust-region") > 0); });
}

}  // namespace parkslam::app
