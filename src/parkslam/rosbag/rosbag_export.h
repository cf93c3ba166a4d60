#ifndef PARKSLAM_ROSBAG_ROSBAG_EXPORT_H_
#define PARKSLAM_ROSBAG_ROSBAG_EXPORT_H_

// A dataset as a ROS 1 bag, the way a car's recorder would write it:
// /vehicle/twist (geometry_msgs/TwistStamped, the wheel speed in
// twist.linear.x), /vehicle/steering_wheel (std_msgs/Float64, radians),
// /imu/data (sensor_msgs/Imu: heading as orientation, yaw rate as
// angular_velocity.z) and /<camera>/image_raw/compressed
// (sensor_msgs/CompressedImage, the dataset's JPEG or PNG files as they
// are), stamped from 1,700,000,000 s on. Also writes the topics.yaml that
// imports it back (rosbag_import.h): a round trip, and a recording to try
// ROS tools on.

#include <filesystem>

namespace parkslam::rosbag_import {

// Throws io::IoError for a dataset it cannot read.
void ExportRosbag(const std::filesystem::path& dataset_dir, const std::filesystem::path& bag,
                  const std::filesystem::path& topics_yaml);

}  // namespace parkslam::rosbag_import

#endif  // PARKSLAM_ROSBAG_ROSBAG_EXPORT_H_
