#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "commands.h"
#include "interruption.h"
#include "parkslam/camera/camera_names.h"
#include "parkslam/io/dataset.h"
#include "parkslam/io/output_guard.h"
#include "parkslam/io/scenario_yaml.h"
#include "parkslam/io/world_plan_yaml.h"
#include "progress.h"
#include "steps.h"

#include <opencv2/imgcodecs.hpp>

#include "parkslam/camera/camera_model.h"
#include "parkslam/harness/frame_renderer.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/rig_yaml.h"
#include "parkslam/sim/world.h"

namespace parkslam::app {
namespace simulate_command {

// Renders the cameras of the default rig along the true trajectory at
// rate_hz into DIR/images/<camera>/<t_ns>.jpg, with images/index.csv
// (t_ns,camera,file) and the rig they were rendered with (images/rig.yaml).
void WriteImages(const std::filesystem::path& dir, const io::Dataset& dataset, double rate_hz) {
  const camera::CameraRig rig = camera::DefaultRig();
  const std::vector<std::string>& names = camera::AllCameraNames();
  const sim::World world = sim::BuildWorld(dataset.scenario->world);
  const harness::FrameRenderer renderer(world, dataset.scenario->world, rig, dataset.seed,
                                        /*whole_images=*/true);
  const Trajectory& truth = dataset.groundtruth_trajectory;
  const TimeNs start = truth.front().t_ns, end = truth.back().t_ns;
  const TimeNs period = FromSeconds(1.0 / rate_hz);
  std::string index = "t_ns,camera,file\n";
  Progress progress("  rendering images", static_cast<int>((end - start) / period) + 1);
  int frame = 0;
  for (TimeNs t = start; t <= end; t += period) {
    const std::vector<cv::Mat> images = renderer.RenderAll(*PoseAt(truth, t), t, names);
    for (size_t c = 0; c < names.size(); ++c) {
      const std::string file = "images/" + names[c] + "/" + std::to_string(t) + ".jpg";
      std::vector<uchar> jpeg;
      cv::imencode(".jpg", images[c], jpeg, {cv::IMWRITE_JPEG_QUALITY, 90});
      io::WriteFileAtomically(
          dir / file, std::string_view(reinterpret_cast<const char*>(jpeg.data()), jpeg.size()));
      index += std::to_string(t) + "," + names[c] + "," + file + "\n";
    }
    progress.Update(++frame);
    InterruptionScope::ThrowIfInterrupted("nothing was written to --out");
  }
  progress.Finish();
  io::WriteFileAtomically(dir / "images" / "rig.yaml", io::RigToYaml(rig));
  io::WriteFileAtomically(dir / "images" / "index.csv", index);
}

}  // namespace simulate_command

void AddSimulateCommand(CLI::App& app) {
  using namespace simulate_command;
  struct Options {
    ScenarioOptions scenario;
    std::uint64_t seed = 1;
    std::string out;
    bool dump_config = false;
    bool dump_plan = false;
    bool images = false;
    double image_rate_hz = 2.0;
    bool force = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "simulate",
      "Simulate a drive through a parking lot and write it as a dataset with ground truth");
  AddScenarioOptions(cmd, &options->scenario);
  cmd->add_option("--seed", options->seed, "Random seed (same seed, same data)")
      ->check(SeedValidator())
      ->capture_default_str();
  cmd->add_option("--out", options->out, "Dataset folder to write");
  cmd->add_flag("--images", options->images,
                "Also render the four fisheye and the front camera along the drive (JPEG, "
                "DIR/images/, with index.csv and the rig)");
  cmd->add_option("--image-rate-hz", options->image_rate_hz, "Frame sets per second with --images")
      ->check(CLI::Range(0.1, 30.0))
      ->capture_default_str();
  cmd->add_flag("--force", options->force,
                "Write into a folder that is not empty, after clearing it (its old images and "
                "data would otherwise mix with the new drive's)");
  cmd->add_flag("--dump-config", options->dump_config,
                "Print the resolved scenario as YAML and exit (a start for your own world)");
  cmd->add_flag("--dump-plan", options->dump_plan,
                "Print the resolved scenario's world slot by slot and its route's waypoints as a "
                "world plan (docs/world_plan.md) and exit");
  cmd->callback([options] {
    const sim::ScenarioConfig scenario = ResolveScenario(options->scenario);
    if (options->dump_config) {
      std::cout << io::ScenarioToYaml(scenario);
      return;
    }
    if (options->dump_plan) {
      std::cout << io::PlanToYaml(io::PlanFromScenario(scenario));
      return;
    }
    if (options->out.empty()) throw CLI::RequiredError("--out");
    io::CheckOutputsSpareInputs({{options->out, "--out", true}}, ScenarioFiles(options->scenario));
    const bool replaces = CheckDatasetFolder(options->out, options->force);
    // As import-rosbag: the dataset is written into a staging folder beside
    // --out and moved there once whole, so that an interrupted or failed run
    // leaves --out as it was (a killed one leaves the staging folder, which
    // the next run's sweep removes).
    io::TemporaryFile staging(StagingTarget(options->out), io::TemporaryFile::Kind::kFolder);
    const InterruptionScope interruption;
    const auto start = std::chrono::steady_clock::now();
    const io::Dataset dataset = SimulateDataset(scenario, options->seed);
    const auto simulated = std::chrono::steady_clock::now();
    std::filesystem::create_directories(staging.path());
    if (options->images) WriteImages(staging.path(), dataset, options->image_rate_hz);
    io::WriteDataset(staging.path(), dataset);
    InterruptionScope::ThrowIfInterrupted("nothing was written to --out");
    if (replaces) ClearDatasetFolder(options->out);
    staging.Commit();
    const auto written = std::chrono::steady_clock::now();
    std::printf("%s\n", DescribeDataset(dataset).c_str());
    std::printf("simulated in %.2f s, written to %s in %.2f s\n",
                std::chrono::duration<double>(simulated - start).count(), options->out.c_str(),
                std::chrono::duration<double>(written - simulated).count());
  });
}

}  // namespace parkslam::app
