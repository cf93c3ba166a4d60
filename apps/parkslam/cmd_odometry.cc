#include <cstdio>

#include "commands.h"
#include "parkslam/common/plausible_ranges.h"
#include "parkslam/io/dataset.h"
#include "parkslam/io/output_guard.h"
#include "parkslam/io/tum.h"
#include "steps.h"

namespace parkslam::app {

void AddOdometryCommand(CLI::App& app) {
  struct Options {
    std::string dataset;
    std::string out;
    double rate_hz = 50.0;
    std::string init;
  };
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "odometry",
      "Kalman dead reckoning (wheel speed, steering, IMU) over a dataset; writes a TUM "
      "trajectory. Without --init it starts at the origin with the yaw of the first AHRS "
      "heading (yaw 0 with a gyro-only IMU).");
  cmd->add_option("DIR", options->dataset, "Dataset folder")->required();
  cmd->add_option("--out", options->out, "TUM trajectory to write")->required();
  cmd->add_option("--rate-hz", options->rate_hz, "Output pose rate")
      ->check(CLI::Range(0.1, kMaxSensorRate_hz))
      ->capture_default_str();
  cmd->add_option("--init", options->init,
                  "Known start pose x,y,yaw in the map frame (metres, radians)");
  cmd->callback([options] {
    io::CheckOutputsSpareInputs({{options->out, "--out"}}, {{options->dataset, "DIR"}});
    const io::Dataset dataset = io::ReadDataset(options->dataset);
    harness::DeadReckoningOptions dr;
    dr.output_rate_hz = options->rate_hz;
    if (!options->init.empty()) dr.initial_pose = ParsePose(options->init, "--init");
    const harness::DeadReckoningResult result = RunOdometry(dataset, dr);
    if (result.poses.empty()) {
      throw std::runtime_error(options->dataset +
                               ": no IMU heading to start from (sensors/imu.csv is empty); "
                               "give --init x,y,yaw");
    }
    io::WriteTum(options->out, harness::ToTrajectory(result.poses));
    std::printf("%zu poses written to %s\n", result.poses.size(), options->out.c_str());
  });
}

}  // namespace parkslam::app
