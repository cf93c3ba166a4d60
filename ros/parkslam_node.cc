// parkslam_node: the live system (live/live_system.h) as a ROS 1 node
// (docs/ros.md). It subscribes to the topics of a topics.yaml, the one that
// `parkslam import-rosbag` reads (the cameras' sensor_msgs/Image or
// CompressedImage, the IMU's sensor_msgs/Imu, wheel speed and steering from
// any message with the field named), and publishes
//   ~odom (nav_msgs/Odometry)      the pose in `map_frame` at every camera
//                                  frame from the first fix on, with its
//                                  covariance;
//   ~state (std_msgs/String, latched) tracking or lost, when it changes;
//   tf map_frame -> base_frame     the same pose;
//   ~map (visualization_msgs/MarkerArray, latched) the map: at the start
//                                  when localizing, every
//                                  publish_map_every_s when mapping;
// and offers ~save_map (std_srvs/Trigger) to write the map now (mapping).
//
// Parameters (private): mode (localize | map), map (localizing: map JSON;
// mapping: a map to update from this drive, mapping/map_update.h), label
// (the update's, default the drive's first stamp), map_out (mapping:
// written at ~save_map and at shutdown), topics
// (topics.yaml), rig (instead of topics.yaml's), options (algorithm options
// YAML, `parkslam map --dump-config`), init ("x,y,yaw" or "entrance", the
// map's: a known start; else localizing globally, and mapping from the
// origin), map_frame (map),
// base_frame (base_link), publish_map_every_s (2), wait_for_perception
// (false; true: every frame perceived, as `localize` does, for a replay).
//
// Messages without a header (std_msgs/Float64) are stamped when they
// arrive (ros::Time::now(): under `rosbag play --clock`, with
// /use_sim_time, the bag's time).
//
// C++17, as ROS 1's message headers need; the live system behind it is
// reached through live_bridge.h.

#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <std_msgs/String.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/transform_broadcaster.h>
#include <topic_tools/shape_shifter.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "live_bridge.h"
#include "map_markers.h"

namespace parkslam::ros_node {
namespace {

struct NodeOptions {
  BridgeOptions bridge;
  std::string map_out;
  std::string map_frame = "map", base_frame = "base_link";
  double publish_map_every_s = 2.0;
};

NodeOptions ReadParameters(const ros::NodeHandle& pnh) {
  NodeOptions o;
  std::string mode = "localize";
  pnh.param<std::string>("mode", mode, mode);
  if (mode != "localize" && mode != "map") {
    throw std::runtime_error("~mode: '" + mode + "' (localize or map)");
  }
  BridgeOptions& b = o.bridge;
  b.mapping = mode == "map";
  pnh.param<std::string>("map", b.map, "");
  pnh.param<std::string>("label", b.label, "");
  pnh.param<std::string>("topics", b.topics, "");
  pnh.param<std::string>("rig", b.rig, "");
  pnh.param<std::string>("options", b.options, "");
  pnh.param<std::string>("init", b.init, "");
  pnh.param<bool>("wait_for_perception", b.wait_for_perception, false);
  pnh.param<std::string>("map_out", o.map_out, "");
  pnh.param<std::string>("map_frame", o.map_frame, o.map_frame);
  pnh.param<std::string>("base_frame", o.base_frame, o.base_frame);
  pnh.param<double>("publish_map_every_s", o.publish_map_every_s, o.publish_map_every_s);
  if (b.topics.empty()) throw std::runtime_error("~topics: missing (the topics.yaml to read)");
  if (!b.mapping && b.map.empty()) throw std::runtime_error("~map: missing (mode localize)");
  if (b.mapping && o.map_out.empty()) throw std::runtime_error("~map_out: missing (mode map)");
  if (!(o.publish_map_every_s > 0.0)) throw std::runtime_error("~publish_map_every_s: must be > 0");
  return o;
}

std::int64_t Nanoseconds(const ros::Time& t) { return static_cast<std::int64_t>(t.toNSec()); }

// The stamp of a message, or its arrival where it has none.
std::int64_t StampOr(const ros::Time& stamp) {
  return Nanoseconds(stamp.isZero() ? ros::Time::now() : stamp);
}

class Node {
 public:
  Node(ros::NodeHandle& nh, ros::NodeHandle& pnh, const NodeOptions& o) : o_(o) {
    odom_ = pnh.advertise<nav_msgs::Odometry>("odom", 50);
    markers_ = pnh.advertise<visualization_msgs::MarkerArray>("map", 1, /*latch=*/true);
    state_ = pnh.advertise<std_msgs::String>("state", 1, /*latch=*/true);
    bridge_ = std::make_unique<LiveBridge>(o.bridge, [this](const BridgePose& p) {
      // ~state when it changes: tracking, or lost (the pose is then the
      // dead reckoning since the last fix, its covariance growing).
      const char* state = p.tracking ? "tracking" : "lost";
      if (state != state_sent_) {
        std_msgs::String m;
        m.data = state;
        state_.publish(m);
        state_sent_ = state;
      }
      // A frame's first estimate (its slots') goes out at once, on ~odom
      // and tf; its second (its tags') on ~odom alone, where a tag moved it.
      if (p.second && p.tags_used == 0) return;
      Publish(p, !p.second);
    });
    if (o.bridge.mapping) {
      save_ = pnh.advertiseService("save_map", &Node::OnSaveMap, this);
      map_timer_ = nh.createWallTimer(ros::WallDuration(o.publish_map_every_s),
                                      [this](const ros::WallTimerEvent&) { PublishMap(); });
    } else {
      PublishMap();
    }
    for (const auto& [name, topic] : bridge_->cameras()) {
      const std::string camera = name, camera_topic = topic;
      subscribers_.push_back(nh.subscribe<topic_tools::ShapeShifter>(
          topic, 10, [this, camera, camera_topic](const topic_tools::ShapeShifter::ConstPtr& m) {
            Guard(camera_topic, [&] { OnImage(camera, *m); });
          }));
    }
    const std::string imu = bridge_->imu_topic();
    subscribers_.push_back(nh.subscribe<sensor_msgs::Imu>(
        imu, 1000,
        [this, imu](const sensor_msgs::Imu::ConstPtr& m) { Guard(imu, [&] { OnImu(*m); }); }));
    for (const bool speed : {true, false}) {
      const BridgeScalarTopic t = speed ? bridge_->wheel_speed() : bridge_->steering();
      subscribers_.push_back(nh.subscribe<topic_tools::ShapeShifter>(
          t.topic, 1000, [this, t, speed](const topic_tools::ShapeShifter::ConstPtr& m) {
            Guard(t.topic, [&] { OnScalar(speed, *m); });
          }));
    }
    ROS_INFO("parkslam: %s", bridge_->Describe().c_str());
  }

  // After the spin: the frames received are perceived and fed, the map
  // (mapping) finished and written.
  void Finish() {
    bridge_->Finish();
    if (o_.bridge.mapping) SaveMap();
    std::printf("parkslam: %s; %d poses published\n", bridge_->Summary().c_str(), published_);
    std::fflush(stdout);
  }

 private:
  // What a callback throws is logged with its topic (at most every 5 s),
  // and the node goes on with the next message.
  template <typename F>
  void Guard(const std::string& topic, F&& work) {
    try {
      work();
    } catch (const std::exception& e) {
      ROS_ERROR_THROTTLE(5.0, "parkslam: %s: %s", topic.c_str(), e.what());
    }
  }

  void OnImage(const std::string& camera, const topic_tools::ShapeShifter& msg) {
    bool fed = false;
    if (msg.getDataType() == "sensor_msgs/CompressedImage") {
      const auto image = msg.instantiate<sensor_msgs::CompressedImage>();
      fed = bridge_->CompressedImage(camera, StampOr(image->header.stamp), image->data.data(),
                                     image->data.size());
    } else if (msg.getDataType() == "sensor_msgs/Image") {
      const auto image = msg.instantiate<sensor_msgs::Image>();
      fed = bridge_->RawImage(camera, StampOr(image->header.stamp), image->encoding,
                              static_cast<int>(image->width), static_cast<int>(image->height),
                              image->step, image->data.data(), image->data.size());
    } else {
      throw std::runtime_error(msg.getDataType() +
                               " (sensor_msgs/Image or CompressedImage are taken)");
    }
    // Mapping: the pose at each frame set is the prediction (the newest
    // keyframe moved on by the dead reckoning).
    if (fed && o_.bridge.mapping) {
      if (const std::optional<BridgePose> p = bridge_->Predicted()) {
        if (p->t_ns != last_predicted_ns_) Publish(*p, true);
        last_predicted_ns_ = p->t_ns;
      }
    }
  }

  void OnImu(const sensor_msgs::Imu& msg) {
    std::optional<double> heading_rad;
    // orientation_covariance[0] = -1: no orientation (a gyro alone).
    if (msg.orientation_covariance[0] != -1.0) {
      const auto& q = msg.orientation;
      heading_rad = std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
    }
    bridge_->Imu(StampOr(msg.header.stamp), msg.angular_velocity.z, heading_rad);
  }

  void OnScalar(bool speed, const topic_tools::ShapeShifter& msg) {
    bytes_.resize(msg.size());
    ros::serialization::OStream stream(bytes_.data(), static_cast<std::uint32_t>(bytes_.size()));
    msg.write(stream);
    bridge_->Scalar(speed, msg.getDataType(), msg.getMessageDefinition(), bytes_.data(),
                    bytes_.size(), Nanoseconds(ros::Time::now()));
  }

  // From the spin's thread or the perception's; roscpp's publishers take
  // both.
  void Publish(const BridgePose& p, bool with_tf) {
    nav_msgs::Odometry odom;
    odom.header.stamp = ros::Time().fromNSec(static_cast<std::uint64_t>(p.t_ns));
    odom.header.frame_id = o_.map_frame;
    odom.child_frame_id = o_.base_frame;
    odom.pose.pose.position.x = p.x_m;
    odom.pose.pose.position.y = p.y_m;
    odom.pose.pose.orientation.z = std::sin(p.yaw_rad / 2.0);
    odom.pose.pose.orientation.w = std::cos(p.yaw_rad / 2.0);
    // (x, y, z, roll, pitch, yaw), row-major; the floor's z, roll and pitch
    // are known.
    const int index[3] = {0, 1, 5};
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        odom.pose.covariance[index[r] * 6 + index[c]] = p.covariance[3 * r + c];
      }
    }
    odom_.publish(odom);
    ++published_;
    if (!with_tf) return;
    geometry_msgs::TransformStamped tf;
    tf.header = odom.header;
    tf.child_frame_id = o_.base_frame;
    tf.transform.translation.x = p.x_m;
    tf.transform.translation.y = p.y_m;
    tf.transform.rotation = odom.pose.pose.orientation;
    tf_.sendTransform(tf);
  }

  void PublishMap() {
    markers_.publish(MapMarkers(bridge_->Map(), o_.map_frame, ros::Time::now()));
  }

  bool SaveMap() {
    try {
      const std::string changes = bridge_->SaveMap(o_.map_out);
      // On stdout too: after the spin, at shutdown, rosconsole is gone.
      std::printf("parkslam: map written to %s%s%s\n", o_.map_out.c_str(),
                  changes.empty() ? "" : "; ", changes.c_str());
      std::fflush(stdout);
      return true;
    } catch (const std::exception& e) {
      ROS_ERROR("parkslam: %s", e.what());
      return false;
    }
  }

  bool OnSaveMap(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response) {
    response.success = SaveMap();
    response.message = response.success ? o_.map_out : "the map could not be written";
    return true;
  }

  NodeOptions o_;
  std::vector<std::uint8_t> bytes_;
  std::int64_t last_predicted_ns_ = 0;
  int published_ = 0;  // under the bridge's lock, or in the spin's thread when mapping
  ros::Publisher odom_, markers_, state_;
  const char* state_sent_ = nullptr;  // under the bridge's lock
  ros::ServiceServer save_;
  ros::WallTimer map_timer_;
  tf2_ros::TransformBroadcaster tf_;
  std::vector<ros::Subscriber> subscribers_;
  // Last, so that it goes first: its perception thread may still publish.
  std::unique_ptr<LiveBridge> bridge_;
};

}  // namespace
}  // namespace parkslam::ros_node

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      std::printf(
          "parkslam_node: the live system as a ROS 1 node (docs/ros.md)\n"
          "  rosrun parkslam parkslam_node _topics:=topics.yaml _map:=map.json\n"
          "  rosrun parkslam parkslam_node _mode:=map _topics:=topics.yaml _map_out:=map.json\n"
          "Parameters (private): mode (localize | map), map (mapping: one to update), label,\n"
          "map_out, topics, rig, options,\n"
          "init (x,y,yaw or entrance), map_frame (map), base_frame (base_link), "
          "publish_map_every_s (2),\n"
          "wait_for_perception (false). Publishes ~odom, ~state, tf and ~map; serves ~save_map.\n");
      return 0;
    }
  }
  ros::init(argc, argv, "parkslam");
  ros::NodeHandle nh, pnh("~");
  try {
    const parkslam::ros_node::NodeOptions options = parkslam::ros_node::ReadParameters(pnh);
    parkslam::ros_node::Node node(nh, pnh, options);
    ros::spin();
    node.Finish();
  } catch (const std::exception& e) {
    ROS_FATAL("parkslam: %s", e.what());
    std::fprintf(stderr, "parkslam_node: %s\n", e.what());
    return 1;
  }
  return 0;
}
