#ifndef PARKSLAM_ROSBAG_ROSBAG_IMPORT_H_
#define PARKSLAM_ROSBAG_ROSBAG_IMPORT_H_

// A ROS 1 bag from a real car as a dataset (docs/your_car.md, "ROS bags"):
// the five cameras (sensor_msgs/Image or CompressedImage), the IMU
// (sensor_msgs/Imu: yaw rate from angular_velocity.z, heading from the
// orientation), and wheel speed and steering from topics and fields the
// user names. Read with Debian's rosbag_storage; the messages are decoded
// from the definitions the bag stores (io/ros1_message.h), so no ROS message
// package is needed.

#include <filesystem>
#include <functional>
#include <map>
#include <string>

#include "parkslam/sensor/odometry_spec.h"
#include "parkslam/sensor/vehicle.h"

namespace parkslam::rosbag_import {

// One scalar channel: a field of a topic's messages, times a scale.
struct ScalarTopic {
  std::string topic;
  std::string field = "data";  // "twist.twist.linear.x", ...
  double scale = 1.0;          // to m/s, or to the steering wheel's radians
};

// topics.yaml:
//   cameras: {front: /cam_front/image_raw/compressed, rear: ..., left: ...,
//             right: ..., front_mono: ...}
//   imu: /imu/data
//   wheel_speed: {topic: /vehicle/speed, field: data, scale: 1.0}
//   steering: {topic: /vehicle/steering_wheel, field: data, scale: 1.0}
//   rig: rig.yaml            # relative to topics.yaml
//   max_set_skew_s: 0.02     # images of one frame set at most this far apart
//   vehicle: {...}           # as in dataset.yaml, every key
//   sensors: {odometry: {...}}
struct TopicsConfig {
  std::map<std::string, std::string> cameras;  // camera name -> topic
  std::string imu;
  ScalarTopic wheel_speed, steering;
  std::filesystem::path rig;
  double max_set_skew_s = 0.02;
  VehicleParameters vehicle;
  OdometrySensorSpec odometry_spec;
};

// Throws io::IoError naming the file, the line and the key.
TopicsConfig LoadTopicsConfig(const std::filesystem::path& path);

struct ImportSummary {
  std::size_t wheel_speeds = 0, steering_angles = 0, imu_samples = 0;
  std::size_t frame_sets = 0;
  std::size_t images_unmatched = 0;  // images left out of every complete set
  std::size_t duplicate_times = 0;   // samples dropped for repeating a time
};

// Writes the dataset into `out` (images first, dataset.yaml last). Throws
// io::IoError naming the bag, the topic and the field for what it cannot
// read: a missing topic, a message type it does not take, a field the
// messages lack, an image encoding other than mono8 / rgb8 / bgr8 or a
// compressed format other than JPEG or PNG. progress(done, total) is
// called as messages are read.
ImportSummary ImportRosbag(const std::filesystem::path& bag, const TopicsConfig& topics,
                           const std::filesystem::path& out,
                           const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace parkslam::rosbag_import

#endif  // PARKSLAM_ROSBAG_ROSBAG_IMPORT_H_
