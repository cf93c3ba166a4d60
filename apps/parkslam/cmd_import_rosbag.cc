// parkslam import-rosbag: a ROS 1 bag from a real car as a dataset
// (docs/your_car.md, "From a ROS bag").

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include "commands.h"
#include "interruption.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/dataset.h"
#include "parkslam/io/output_guard.h"
#include "parkslam/rosbag/rosbag_export.h"
#include "parkslam/rosbag/rosbag_import.h"
#include "progress.h"

namespace parkslam::app {

namespace {

// The import fails where check-dataset would fail the dataset it writes (a
// wheel-speed scale of 1e6, a zero quaternion, two cameras on one topic):
// the two agree. Gaps in a stream are not refused (a real bag has them);
// check-dataset lists them.
void RefuseWhatCheckDatasetRefuses(const std::filesystem::path& staging, const std::string& bag,
                                   const std::string& out) {
  const io::DatasetCheck check = io::CheckDataset(staging, /*max_gap_s=*/3600.0);
  if (check.ok()) return;
  std::string message = bag + ": the dataset it gives fails check-dataset; nothing was written:";
  const std::string staged = staging.string();
  for (size_t k = 0; k < check.errors.size() && k < 5; ++k) {
    std::string error = check.errors[k];
    // Name the files as the dataset will have them, not the staging folder.
    for (size_t at = error.find(staged); at != std::string::npos;
         at = error.find(staged, at + out.size())) {
      error.replace(at, staged.size(), out);
    }
    message += "\n  " + error;
  }
  if (check.errors.size() > 5) {
    message += "\n  (and " + std::to_string(check.errors.size() - 5) + " more)";
  }
  throw std::runtime_error(message);
}

}  // namespace

void AddImportRosbagCommand(CLI::App& app) {
  struct Options {
    std::string bag, topics, out;
    bool force = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "import-rosbag",
      "Turn a ROS 1 bag into a dataset: the five cameras (sensor_msgs/Image or "
      "CompressedImage) in frame sets, the IMU (sensor_msgs/Imu), wheel speed and steering "
      "from the topics and fields named in --topics; then map --images and localize --images "
      "run on it");
  cmd->add_option("BAG", options->bag, "ROS 1 bag")->required()->check(CLI::ExistingFile);
  cmd->add_option("--topics", options->topics,
                  "topics.yaml: camera topics, imu, wheel_speed and steering {topic, field, "
                  "scale}, rig, vehicle, sensors (docs/your_car.md)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", options->out, "Dataset folder to write")->required();
  cmd->add_flag("--force", options->force, "Write into a folder that is not empty, clearing it");
  cmd->callback([options] {
    const rosbag_import::TopicsConfig topics = rosbag_import::LoadTopicsConfig(options->topics);
    io::CheckOutputsSpareInputs(
        {{options->out, "--out", true}},
        {{options->bag, "BAG"}, {options->topics, "--topics"}, {topics.rig.string(), "rig"}});
    const bool replaces = CheckDatasetFolder(options->out, options->force);
    // The dataset is written into a staging folder beside --out and moved
    // there once whole and checked: a failed or interrupted import leaves
    // --out as it was.
    io::TemporaryFile staging(StagingTarget(options->out), io::TemporaryFile::Kind::kFolder);
    const InterruptionScope interruption;
    Progress progress("  reading the bag", 1000);
    const rosbag_import::ImportSummary s = rosbag_import::ImportRosbag(
        options->bag, topics, staging.path(), [&progress](std::size_t done, std::size_t total) {
          InterruptionScope::ThrowIfInterrupted("nothing was written to --out");
          progress.Update(static_cast<int>(1000 * done / std::max<std::size_t>(total, 1)));
        });
    progress.Finish();
    InterruptionScope::ThrowIfInterrupted("nothing was written to --out");
    RefuseWhatCheckDatasetRefuses(staging.path(), options->bag, options->out);
    if (replaces) ClearDatasetFolder(options->out);
    staging.Commit();
    std::printf(
        "%zu wheel speeds, %zu steering angles, %zu IMU samples, %zu frame sets of images "
        "(%zu images in no complete set, %zu samples dropped for a repeated time)\n"
        "dataset written to %s; check it with: parkslam check-dataset %s\n",
        s.wheel_speeds, s.steering_angles, s.imu_samples, s.frame_sets, s.images_unmatched,
        s.duplicate_times, options->out.c_str(), options->out.c_str());
  });
}

void AddExportRosbagCommand(CLI::App& app) {
  struct Options {
    std::string dataset, out, topics;
  };
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "export-rosbag",
      "Write a dataset as a ROS 1 bag as a car's recorder would (TwistStamped speed, Float64 "
      "steering, Imu, CompressedImage per camera), and the topics.yaml that imports it back");
  cmd->add_option("DIR", options->dataset, "Dataset folder")->required();
  cmd->add_option("--out", options->out, "ROS 1 bag to write")->required();
  cmd->add_option("--topics", options->topics, "topics.yaml to write (default: beside the bag)");
  cmd->callback([options] {
    if (options->topics.empty()) {
      options->topics = (std::filesystem::path(options->out).parent_path() /
                         (std::filesystem::path(options->out).stem().string() + "_topics.yaml"))
                            .string();
    }
    io::CheckOutputsSpareInputs({{options->out, "--out"}, {options->topics, "--topics"}},
                                {{options->dataset, "DIR"}});
    rosbag_import::ExportRosbag(options->dataset, options->out, options->topics);
    std::printf("wrote %s and %s\n", options->out.c_str(), options->topics.c_str());
  });
}

}  // namespace parkslam::app
