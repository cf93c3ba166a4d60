#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "parkslam/eval/map_metrics.h"
#include "parkslam/harness/dead_reckoning.h"
#include "parkslam/harness/kidnap.h"
#include "parkslam/io/dataset.h"
#include "parkslam/io/map_json.h"
#include "parkslam/io/output_guard.h"
#include "parkslam/io/tum.h"
#include "parkslam/localization/localization_run.h"
#include "parkslam/localization/localizer.h"
#include "progress.h"
#include "steps.h"

namespace parkslam::app {

namespace localize_command {

struct Options {
  std::string map, dataset, out, init, log;
  bool global = false;
  int kidnap_trials = 0;
  PixelOptions pixels;
  ConfigOptions config;
};

void PrintRun(const localization::LocalizationRun& run, const harness::SensorStream& stream,
              const localization::Localizer& localizer, const SemanticMap& map) {
  const Trajectory& trajectory = run.tracked;
  std::vector<double> update_ms = run.update_ms;
  std::sort(update_ms.begin(), update_ms.end());
  const int frames = run.frames, tracking = static_cast<int>(trajectory.size());
  const double duration_s = ToSeconds(trajectory.back().t_ns - trajectory.front().t_ns);
  std::printf(
      "%d camera frames, %d tracked (%.1f %%), %.1f Hz; lost %d times, "
      "(re)localized %d times; update median %.3f ms, max %.3f ms\n",
      frames, tracking, 100.0 * tracking / std::max(frames, 1),
      duration_s > 0 ? (trajectory.size() - 1) / duration_s : 0.0, run.lost_events,
      run.relocalizations, update_ms[update_ms.size() / 2], update_ms.back());
  std::printf(
      "%s\n",
      DescribeLandmarkUse(run, localization::MeasureSlotCoverage(run.estimates, map)).c_str());
  const std::string stream_faults = stream.DescribeFaults();
  if (!stream_faults.empty()) std::printf("%s\n", stream_faults.c_str());
  const std::string odometry_faults = DescribeOdometryFaults(localizer.odometry_stats());
  if (!odometry_faults.empty()) std::printf("%s\n", odometry_faults.c_str());
  const std::string wheel = DescribeWheelScale(localizer);
  if (!wheel.empty()) std::printf("%s\n", wheel.c_str());
}

// Kidnapped-robot trials on the drive, against its ground truth.
void RunKidnapTrials(const Options& o, const AlgorithmOptions& config, const SemanticMap& map,
                     const io::Dataset& dataset) {
  if (dataset.groundtruth_trajectory.empty() || !dataset.groundtruth_map) {
    throw std::runtime_error(o.dataset + ": --kidnap-trials needs the dataset's ground truth");
  }
  // The truth in the map's frame: align the map onto the true lot.
  const SE2 T_map_world = eval::EvaluateMap(map, *dataset.groundtruth_map).T_truth_map.inverse();
  const Trajectory truth_map = Transformed(T_map_world, dataset.groundtruth_trajectory);
  harness::KidnapOptions kidnap;
  kidnap.trials = o.kidnap_trials;
  Progress trials("  kidnap trials", kidnap.trials);
  const harness::KidnapResult k =
      harness::RunKidnapTrials(map, dataset.log, truth_map, config.localizer,
                               odometry::EkfOptionsFromSpec(dataset.odometry_spec, dataset.vehicle),
                               kidnap, [&trials](int done, int) { trials.Update(done); });
  trials.Finish();
  std::vector<double> times = k.recovery_s;
  std::sort(times.begin(), times.end());
  std::printf(
      "kidnapped-robot trials: %d of %d recovered within %.0f s of driving "
      "(%.1f %%); recovery median %.2f s, max %.2f s\n",
      k.successes, k.trials, kidnap.max_recovery_s, 100.0 * k.success_rate(),
      times.empty() ? 0.0 : times[times.size() / 2], times.empty() ? 0.0 : times.back());
}

void Run(const Options& o) {
  io::CheckOutputsSpareInputs({{o.out, "--out"}, {o.log, "--log"}},
                              {{o.dataset, "DIR"}, {o.map, "--map"}});
  const AlgorithmOptions config = o.config.Load();
  const SemanticMap map = io::ReadMap(o.map);
  const io::Dataset dataset = io::ReadDataset(o.dataset);
  localization::Localizer localizer(
      map, config.localizer, odometry::EkfOptionsFromSpec(dataset.odometry_spec, dataset.vehicle));
  if (!o.init.empty()) {
    const Eigen::Vector3d sigma =
        o.init == "entrance" ? config.localizer.EntranceSigmas() : Eigen::Vector3d(0.5, 0.5, 0.1);
    localizer.SetPose(io::ParseStartPose(o.init, map, "--init", o.map),
                      sigma.cwiseAbs2().asDiagonal());
  }
  if (!o.log.empty() && (dataset.groundtruth_trajectory.empty() || !dataset.groundtruth_map)) {
    throw std::runtime_error(o.dataset + ": --log needs the dataset's ground truth");
  }
  harness::SensorStream stream(dataset, o.pixels.Stream(o.dataset, config.front_end));
  stream.SearchTagsFor(localizer);
  SensorSource& source = stream.source();
  const DriveSpan span = SpanOf(dataset.log);
  Progress progress("  localizing", span.TotalTenths());
  const localization::LocalizationRun run = localization::RunLocalization(
      source, &localizer, [&](TimeNs t_ns) { progress.Update(span.Tenths(t_ns)); });
  progress.Finish();
  const Trajectory& trajectory = run.tracked;
  if (trajectory.empty()) {
    throw std::runtime_error(o.dataset + ": the car was never localized on " + o.map);
  }
  io::WriteTum(o.out, trajectory);
  if (!o.log.empty()) {
    // The map may live in its own frame: the log is in the truth's.
    const SE2 T_world_map = eval::EvaluateMap(map, *dataset.groundtruth_map).T_truth_map;
    io::WriteNumericCsv(
        o.log, LocalizationLog(run.estimates, T_world_map, dataset.groundtruth_trajectory));
  }
  PrintRun(run, stream, localizer, map);
  std::printf("%zu poses written to %s\n", trajectory.size(), o.out.c_str());
  if (o.kidnap_trials > 0) RunKidnapTrials(o, config, map, dataset);
}

}  // namespace localize_command

void AddLocalizeCommand(CLI::App& app) {
  using namespace localize_command;
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "localize",
      "Localize a drive on a map built before: the pose at every camera frame, from slot "
      "corners and tags associated by ID and gated nearest neighbour; writes the tracked "
      "poses as TUM");
  cmd->add_option("--map", options->map, "Map JSON")->required();
  cmd->add_option("DIR", options->dataset, "Dataset folder")->required();
  cmd->add_option("--out", options->out, "TUM trajectory to write")->required();
  cmd->add_option(
      "--log", options->log,
      "Also write the estimate at every camera frame beside the truth, in the lot's "
      "frame (localization.csv for `parkslam report`; needs the dataset's ground truth)");
  AddPixelOptions(cmd, &options->pixels);
  AddConfigOptions(cmd, &options->config);
  cmd->add_option("--kidnap-trials", options->kidnap_trials,
                  "Also run this many kidnapped-robot trials on the drive: the belief is "
                  "replaced by a confident wrong pose; a trial succeeds when the localizer is "
                  "back within 0.5 m of the truth within 5 s of driving (needs ground truth)")
      ->check(CLI::Range(0, 10000));
  auto* init = cmd->add_option("--init", options->init,
                               "Known start pose x,y,yaw in the map frame (metres, radians), or "
                               "'entrance': where the map's own drive began (a car that starts "
                               "its drives at the lot's entrance)");
  auto* global = cmd->add_flag("--global", options->global,
                               "Start with an unknown pose and localize globally (the default "
                               "without --init)");
  init->excludes(global);
  cmd->callback([options] { Run(*options); });
}

}  // namespace parkslam::app
