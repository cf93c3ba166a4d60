#include "parkslam/rosbag/rosbag_export.h"

#include <rosbag/bag.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "parkslam/io/atomic_file.h"
#include "parkslam/io/dataset.h"
#include "parkslam/io/image_folder.h"
#include "parkslam/io/image_header.h"
#include "parkslam/io/io_error.h"
#include "parkslam/io/yaml_util.h"
#include "parkslam/rosbag/ros1_writer.h"

namespace parkslam::rosbag_import {
namespace fs = std::filesystem;

namespace {

constexpr std::int64_t kEpoch_ns = 1'700'000'000'000'000'000;

ros::Time RosTime(std::int64_t stamp_ns) {
  return ros::Time().fromNSec(static_cast<std::uint64_t>(stamp_ns));
}

}  // namespace

void ExportRosbag(const fs::path& dataset_dir, const fs::path& bag_path,
                  const fs::path& topics_yaml) {
  const io::Dataset dataset = io::ReadDataset(dataset_dir);
  std::vector<io::ImageIndexEntry> images;
  if (fs::exists(dataset_dir / "images/index.csv")) images = io::ReadImageIndex(dataset_dir);
  // Written beside the bag and renamed over it once whole, so that a signal,
  // a full disk or a second run never leaves a half-written bag at its path.
  io::TemporaryFile temporary(bag_path);
  // A Bag whose write failed throws again from its destructor (its close()
  // flushes once more), which would end the process; so a failed one is
  // left open, once, as the command ends with the error.
  auto bag = std::make_unique<rosbag::Bag>();
  try {
    bag->open(temporary.path().string(), rosbag::bagmode::Write);
    for (const WheelSpeed& s : dataset.log.wheel_speeds) {
      const std::int64_t t = kEpoch_ns + s.t_ns;
      bag->write("/vehicle/twist", RosTime(t), SpeedStamped(t, s.speed_mps));
    }
    for (const SteeringAngle& s : dataset.log.steering_angles) {
      bag->write("/vehicle/steering_wheel", RosTime(kEpoch_ns + s.t_ns),
                 Float64(s.steering_wheel_rad));
    }
    for (const ImuSample& s : dataset.log.imu_samples) {
      const std::int64_t t = kEpoch_ns + s.t_ns;
      bag->write("/imu/data", RosTime(t), Imu(t, s.heading_rad, s.yaw_rate_radps));
    }
    for (const io::ImageIndexEntry& e : images) {
      io::CheckImageEnds(dataset_dir / e.file);  // a cut image is not passed on
      const std::string bytes = io::ReadTextFile(dataset_dir / e.file, io::kMaxImageBytes);
      const std::int64_t t = kEpoch_ns + e.t_ns;
      const bool png = fs::path(e.file).extension() == ".png";
      bag->write("/" + e.camera + "/image_raw/compressed", RosTime(t),
                 Compressed(t, png ? "png" : "jpeg",
                            std::vector<std::uint8_t>(bytes.begin(), bytes.end())));
    }
    bag->close();
  } catch (const io::IoError&) {
    static_cast<void>(bag.release());  // see above
    throw;
  } catch (const std::exception&) {
    // rosbag's own words name the temporary; errno says why (a full disk).
    const int write_errno = errno;
    static_cast<void>(bag.release());
    io::ThrowIoError(bag_path.string(), 0, "",
                     write_errno != 0 ? "cannot write: " + std::string(std::strerror(write_errno))
                                      : std::string("cannot write the bag"));
  }
  bag.reset();
  // The topics.yaml that reads it back.
  std::string topics = "# parkslam import-rosbag topics for " + bag_path.filename().string() +
                       " (written by export-rosbag)\ncameras:\n";
  std::vector<std::string> cameras;
  for (const io::ImageIndexEntry& e : images) {
    if (std::find(cameras.begin(), cameras.end(), e.camera) == cameras.end()) {
      cameras.push_back(e.camera);
      topics += "  " + e.camera + ": /" + e.camera + "/image_raw/compressed\n";
    }
  }
  topics +=
      "imu: /imu/data\n"
      "wheel_speed: {topic: /vehicle/twist, field: twist.linear.x}\n"
      "steering: {topic: /vehicle/steering_wheel, field: data}\n";
  const fs::path base = fs::absolute(topics_yaml).parent_path();
  topics += "rig: \"" +
            fs::relative(fs::absolute(dataset_dir / "images/rig.yaml"), base).generic_string() +
            "\"\nvehicle:\n";
  io::yaml_util::AppendVehicleYaml(dataset.vehicle, 2, &topics);
  topics += "sensors:\n  odometry:\n";
  io::yaml_util::AppendOdometrySpecYaml(dataset.odometry_spec, 4, &topics);
  io::WriteFileAtomically(topics_yaml, topics);
  temporary.Commit();
}

}  // namespace parkslam::rosbag_import
