#ifndef PARKSLAM_ROS_LIVE_BRIDGE_H_
#define PARKSLAM_ROS_LIVE_BRIDGE_H_

// The node's side of the live system (live/live_system.h), in plain types.
// ROS 1's generated message headers do not compile as C++20 (their
// allocators use std::allocator<void>::rebind, removed in C++20), and the
// core is C++20: so the node's ROS part is C++17 and sees only this header,
// and this bridge (C++20, no ROS header) does the rest: topics.yaml, the
// rig, the options, decoding the images and the scalar messages, frame
// sets, the live system, the map file.
//
// Times are ROS times in nanoseconds, in and out; inside, the first stamp
// seen is the drive's zero.

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace parkslam::ros_node {

struct BridgeOptions {
  bool mapping = false;
  // Localizing: the map JSON; mapping: a map to update from this drive
  // (mapping/map_update.h), or none.
  std::string map;
  std::string label;    // mapping onto a map: the update's (default: the first stamp)
  std::string topics;   // topics.yaml (import-rosbag's)
  std::string rig;      // instead of topics.yaml's rig, when given
  std::string options;  // algorithm options YAML, when given
  std::string init;     // "x,y,yaw": a known start, when given
  bool wait_for_perception = false;
};

// A pose at a camera frame (localizing: the estimate, from the first fix
// on; mapping: the prediction), in the map frame; covariance of (x, y, yaw), row-major,
// zero where none is known.
struct BridgePose {
  std::int64_t t_ns = 0;
  double x_m = 0.0, y_m = 0.0, yaw_rad = 0.0;
  std::array<double, 9> covariance{};
  bool second = false;   // a frame's second estimate (its tags'), same time
  bool tracking = true;  // false: lost, the dead reckoning since the last fix
  int slots_used = 0, tags_used = 0;
};

// The map as drawn (map_markers.h).
struct BridgeMap {
  struct Slot {
    std::string id;
    bool temporary = false;
    std::array<std::array<double, 2>, 4> corners_m{};
    std::array<bool, 4> corner_observed{};
  };
  struct Tag {
    int id = 0;
    double x_m = 0.0, y_m = 0.0, yaw_rad = 0.0;
  };
  std::vector<Slot> slots;
  std::vector<Tag> tags;
};

struct BridgeScalarTopic {
  std::string topic, field;
};

class LiveBridge {
 public:
  // Reads topics.yaml, the rig, the options and (localizing) the map, and
  // starts the live system. on_pose (localizing) gets each estimate from
  // the thread that made it, under the system's lock: it must be quick.
  // Throws std::runtime_error naming the file and the key.
  LiveBridge(const BridgeOptions& options, std::function<void(const BridgePose&)> on_pose);
  ~LiveBridge();
  LiveBridge(const LiveBridge&) = delete;
  LiveBridge& operator=(const LiveBridge&) = delete;

  // From topics.yaml: camera name and topic (the reference camera first),
  // the IMU's topic, wheel speed and steering.
  const std::vector<std::pair<std::string, std::string>>& cameras() const;
  std::string imu_topic() const;
  BridgeScalarTopic wheel_speed() const;
  BridgeScalarTopic steering() const;
  std::string Describe() const;  // what it runs on, for the log

  // A camera's image: JPEG or PNG bytes (sensor_msgs/CompressedImage), or
  // raw mono8 / rgb8 / bgr8 rows (sensor_msgs/Image). Throws
  // std::runtime_error for what it cannot take (naming the camera). Returns
  // whether a frame set was completed and fed.
  bool CompressedImage(const std::string& camera, std::int64_t t_ns, const std::uint8_t* data,
                       std::size_t size);
  bool RawImage(const std::string& camera, std::int64_t t_ns, const std::string& encoding,
                int width, int height, std::size_t step, const std::uint8_t* data,
                std::size_t size);
  void Imu(std::int64_t t_ns, double yaw_rate_radps, std::optional<double> heading_rad);
  // A wheel speed or steering message of any type: its definition (as ROS
  // gives it, the type's full text) and its serialized bytes; the field of
  // topics.yaml is read from it, times its scale. A stamp from the
  // message's header.stamp where it has one, else stamp_if_none_ns.
  // Throws std::runtime_error for a message without the field.
  void Scalar(bool wheel_speed, const std::string& datatype, const std::string& definition,
              const std::uint8_t* data, std::size_t size, std::int64_t stamp_if_none_ns);

  // The pose at the newest odometry (live::LiveSystem::PredictedPose).
  std::optional<BridgePose> Predicted() const;
  BridgeMap Map() const;
  // Writes the map as it stands, atomically; mapping onto a map, that map
  // updated from it (and returns what changed). Throws std::runtime_error.
  std::string SaveMap(const std::string& path) const;
  // Waits for the frames received and (mapping) finishes the map.
  void Finish();
  // Frame sets, perceived, dropped, latency.
  std::string Summary() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace parkslam::ros_node

#endif  // PARKSLAM_ROS_LIVE_BRIDGE_H_
