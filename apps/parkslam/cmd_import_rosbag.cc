// parkslam import-rosbag: a ROS 1 bag from a real car as a dataset
// (docs/your_car.md, "From a ROS bag").

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "commands.h"
#include "parkslam/io/output_guard.h"
#include "parkslam/rosbag/rosbag_export.h"
#include "parkslam/rosbag/rosbag_import.h"
#include "progress.h"

namespace parkslam::app {

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
        {{options->out, "--out"}},
        {{options->bag, "BAG"}, {options->topics, "--topics"}, {topics.rig.string(), "rig"}});
    PrepareDatasetFolder(options->out, options->force);
    Progress progress("  reading the bag", 1000);
    const rosbag_import::ImportSummary s = rosbag_import::ImportRosbag(
        options->bag, topics, options->out, [&progress](std::size_t done, std::size_t total) {
          progress.Update(static_cast<int>(1000 * done / std::max<std::size_t>(total, 1)));
        });
    progress.Finish();
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
