#include "parkslam/rosbag/rosbag_import.h"

#include <ros/serialization.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <stdexcept>
#include <vector>

#include "parkslam/camera/camera_names.h"
#include "parkslam/common/field_checker.h"
#include "parkslam/common/plausible_ranges.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/dataset.h"
#include "parkslam/io/io_error.h"
#include "parkslam/io/rig_yaml.h"
#include "parkslam/io/ros1_message.h"
#include "parkslam/io/text_util.h"
#include "parkslam/io/yaml_util.h"

namespace parkslam::rosbag_import {
namespace fs = std::filesystem;
using io::ThrowIoError;

namespace {

ScalarTopic ReadScalarTopic(const io::yaml_util::YamlReader& r, const YAML::Node& node,
                            const std::string& path) {
  r.ExpectMap(node, path);
  r.CheckKeys(node, path, {"topic", "field", "scale"});
  if (!node["topic"]) r.Fail(node, path + ".topic", "missing key");
  ScalarTopic t;
  t.topic = r.String(node["topic"], path + ".topic");
  if (node["field"]) t.field = r.String(node["field"], path + ".field");
  if (node["scale"]) t.scale = r.DoubleIn(node["scale"], path + ".scale", -1e6, 1e6, "");
  return t;
}

// An image file waiting for its frame set: written under its absolute time.
struct PendingImage {
  std::int64_t stamp_ns;
  fs::path file;
  std::string extension;
};

struct Channel {
  std::string bag_name;
  std::string topic;
  std::string datatype;
  io::ros1::MessageSpec spec;
};

std::int64_t StampOf(const std::map<std::string, io::ros1::Leaf>& leaves,
                     const rosbag::MessageInstance& m) {
  const auto it = leaves.find("header.stamp");
  if (it != leaves.end() && it->second.ns > 0) return it->second.ns;
  return static_cast<std::int64_t>(m.getTime().toNSec());
}

std::string FieldsOf(const io::ros1::MessageSpec& spec, const std::vector<std::uint8_t>& bytes) {
  std::string list;
  io::ros1::Decode(spec, bytes.data(), bytes.size(), [&](const io::ros1::Leaf& leaf) {
    if (list.size() < 200) list += (list.empty() ? "" : ", ") + leaf.path;
  });
  return list;
}

// Encoded bytes and file extension of one image message.
std::pair<std::string, std::string> EncodedImage(const Channel& c,
                                                 const std::map<std::string, io::ros1::Leaf>& f) {
  auto need = [&](const char* field) -> const io::ros1::Leaf& {
    const auto it = f.find(field);
    if (it == f.end()) ThrowIoError(c.bag_name, 0, c.topic, std::string("no field ") + field);
    return it->second;
  };
  const io::ros1::Leaf& data = need("data");
  if (c.datatype == "sensor_msgs/CompressedImage") {
    const std::string format = need("format").text;
    std::string extension;
    if (format.find("jpeg") != std::string::npos || format.find("jpg") != std::string::npos) {
      extension = ".jpg";
    } else if (format.find("png") != std::string::npos) {
      extension = ".png";
    } else {
      ThrowIoError(c.bag_name, 0, c.topic + ".format",
                   "'" + format + "': only JPEG and PNG images are taken");
    }
    return {std::string(reinterpret_cast<const char*>(data.bytes), data.size), extension};
  }
  const int height = static_cast<int>(need("height").number);
  const int width = static_cast<int>(need("width").number);
  const std::size_t step = static_cast<std::size_t>(need("step").number);
  const std::string encoding = need("encoding").text;
  int type = 0;
  if (encoding == "mono8") {
    type = CV_8UC1;
  } else if (encoding == "rgb8" || encoding == "bgr8") {
    type = CV_8UC3;
  } else {
    ThrowIoError(c.bag_name, 0, c.topic + ".encoding",
                 "'" + encoding + "': only mono8, rgb8 and bgr8 images are taken");
  }
  const std::size_t row_bytes = static_cast<std::size_t>(width) * (type == CV_8UC1 ? 1 : 3);
  if (height <= 0 || width <= 0 || step < row_bytes || data.size < step * height) {
    ThrowIoError(c.bag_name, 0, c.topic + ".data",
                 "an image of " + std::to_string(width) + " x " + std::to_string(height) +
                     " with step " + std::to_string(step) + " needs more than its " +
                     std::to_string(data.size) + " bytes");
  }
  cv::Mat image(height, width, type, const_cast<std::uint8_t*>(data.bytes), step);
  cv::Mat bgr = image;
  if (encoding == "rgb8") cv::cvtColor(image, bgr, cv::COLOR_RGB2BGR);
  std::vector<std::uint8_t> jpeg;
  cv::imencode(".jpg", bgr, jpeg, {cv::IMWRITE_JPEG_QUALITY, 95});
  return {std::string(jpeg.begin(), jpeg.end()), ".jpg"};
}

// Sorts samples by time and drops those that repeat a time.
template <typename T>
std::size_t SortUnique(std::vector<T>* samples) {
  std::stable_sort(samples->begin(), samples->end(),
                   [](const T& a, const T& b) { return a.t_ns < b.t_ns; });
  const auto end = std::unique(samples->begin(), samples->end(),
                               [](const T& a, const T& b) { return a.t_ns == b.t_ns; });
  const std::size_t dropped = static_cast<std::size_t>(samples->end() - end);
  samples->erase(end, samples->end());
  return dropped;
}

// What each topic is, from the bag's connections.
std::map<std::string, Channel> ReadChannels(rosbag::View& view, const std::string& bag_name) {
  std::map<std::string, Channel> channels;
  for (const rosbag::ConnectionInfo* c : view.getConnections()) {
    if (channels.contains(c->topic)) continue;
    try {
      channels[c->topic] = {bag_name, c->topic, c->datatype,
                            io::ros1::ParseDefinition(c->datatype, c->msg_def)};
    } catch (const std::invalid_argument& e) {
      ThrowIoError(bag_name, 0, c->topic, e.what());
    }
  }
  return channels;
}

// Fails unless the bag has the topic (of one of the types, when given).
void RequireTopic(const std::map<std::string, Channel>& channels, const std::string& bag_name,
                  const std::string& topic, const std::string& key,
                  const std::set<std::string>& types) {
  const auto it = channels.find(topic);
  if (it == channels.end()) {
    std::string have;
    for (const auto& [name, c] : channels) have += (have.empty() ? "" : ", ") + name;
    ThrowIoError(bag_name, 0, key, "topic " + topic + " is not in the bag (it has " + have + ")");
  }
  if (!types.empty() && !types.contains(it->second.datatype)) {
    ThrowIoError(bag_name, 0, key,
                 "topic " + topic + " is " + it->second.datatype + ", which is not taken here");
  }
}

// What the messages of the used topics gave: the sensor log (absolute
// times), the image files waiting for their frame sets, the first stamp.
struct BagContents {
  std::map<std::string, std::vector<PendingImage>> images;
  SensorLog log;
  std::int64_t first_ns = INT64_MAX;
};

// Reads the bag's messages in order; decoding errors name the topic.
class MessageReader {
 public:
  MessageReader(const TopicsConfig& topics, const std::map<std::string, Channel>& channels,
                const std::map<std::string, std::string>& camera_of_topic,
                const std::string& bag_name, const fs::path& out)
      : topics_(topics),
        channels_(channels),
        camera_of_topic_(camera_of_topic),
        bag_name_(bag_name),
        out_(out) {}

  BagContents Read(rosbag::View& view,
                   const std::function<void(std::size_t, std::size_t)>& progress) {
    const std::size_t total = view.size();
    std::size_t done = 0;
    for (const rosbag::MessageInstance& m : view) {
      if (progress) progress(++done, total);
      const auto channel = channels_.find(m.getTopic());
      if (channel == channels_.end()) continue;
      const Channel& c = channel->second;
      const bool camera = camera_of_topic_.contains(c.topic);
      const bool used = camera || c.topic == topics_.imu || c.topic == topics_.wheel_speed.topic ||
                        c.topic == topics_.steering.topic;
      if (!used) continue;
      bytes_.resize(m.size());
      ros::serialization::OStream stream(bytes_.data(), static_cast<std::uint32_t>(bytes_.size()));
      m.write(stream);
      try {
        if (camera) ReadImage(c, m);
        if (c.topic == topics_.imu) ReadImu(c, m);
        if (c.topic == topics_.wheel_speed.topic) {
          const auto [stamp, value] = Scalar(topics_.wheel_speed, "wheel_speed", c, m);
          Plausible(value, kMaxWheelSpeed_mps, "wheel_speed", c.topic, stamp, "m/s");
          contents_.log.wheel_speeds.push_back({stamp, value});
          contents_.first_ns = std::min(contents_.first_ns, stamp);
        }
        if (c.topic == topics_.steering.topic) {
          const auto [stamp, value] = Scalar(topics_.steering, "steering", c, m);
          Plausible(value, kMaxSteeringWheelAngle_rad, "steering", c.topic, stamp, "rad");
          contents_.log.steering_angles.push_back({stamp, value});
          contents_.first_ns = std::min(contents_.first_ns, stamp);
        }
      } catch (const std::invalid_argument& e) {
        ThrowIoError(bag_name_, 0, c.topic, e.what());
      }
    }
    return std::move(contents_);
  }

 private:
  // A scaled number beyond what a car reports (common/plausible_ranges.h),
  // named by the bag, the key of topics.yaml, the topic and the stamp, not
  // by the dataset file it would have become.
  void Plausible(double value, double max_abs, const char* key, const std::string& topic,
                 std::int64_t stamp, std::string_view unit) const {
    if (std::isfinite(value) && std::abs(value) <= max_abs) return;
    ThrowIoError(bag_name_, 0, key,
                 "topic " + topic + " at stamp " + std::to_string(stamp) +
                     " ns: " + io::text::BeyondPlausible(value, max_abs, unit) +
                     " (after topics.yaml's scale)");
  }

  void ReadImage(const Channel& c, const rosbag::MessageInstance& m) {
    const auto leaves = io::ros1::DecodeFields(
        c.spec, bytes_.data(), bytes_.size(),
        {"header.stamp", "data", "format", "height", "width", "step", "encoding"});
    const std::int64_t stamp = StampOf(leaves, m);
    const auto [encoded, extension] = EncodedImage(c, leaves);
    const std::string& name = camera_of_topic_.at(c.topic);
    const fs::path file = out_ / "images" / name / ("stamp_" + std::to_string(stamp) + extension);
    fs::create_directories(file.parent_path());
    io::WriteFileAtomically(file, encoded);
    contents_.images[name].push_back({stamp, file, extension});
    contents_.first_ns = std::min(contents_.first_ns, stamp);
  }

  void ReadImu(const Channel& c, const rosbag::MessageInstance& m) {
    const auto f = io::ros1::DecodeFields(
        c.spec, bytes_.data(), bytes_.size(),
        {"header.stamp", "orientation.x", "orientation.y", "orientation.z", "orientation.w",
         "orientation_covariance[0]", "angular_velocity.z"});
    const double x = f.at("orientation.x").number, y = f.at("orientation.y").number,
                 z = f.at("orientation.z").number, w = f.at("orientation.w").number;
    const std::int64_t stamp = StampOf(f, m);
    // sensor_msgs/Imu: orientation_covariance[0] = -1 means no orientation
    // (a gyro-only IMU).
    const auto covariance = f.find("orientation_covariance[0]");
    const bool has_heading = covariance == f.end() || covariance->second.number != -1.0;
    ImuSample sample{stamp, f.at("angular_velocity.z").number, std::nullopt};
    Plausible(sample.yaw_rate_radps, kMaxYawRate_radps, "imu", c.topic, stamp, "rad/s");
    if (has_heading) {
      // A rotation's quaternion has norm 1; drivers round it, a zero or
      // runaway one is no orientation at all (atan2 would make it heading 0).
      const double norm = std::sqrt(x * x + y * y + z * z + w * w);
      if (!(norm >= 0.5 && norm <= 2.0)) {
        ThrowIoError(bag_name_, 0, "imu",
                     "topic " + c.topic + " at stamp " + std::to_string(stamp) +
                         " ns: orientation (" + Limit(x) + ", " + Limit(y) + ", " + Limit(z) +
                         ", " + Limit(w) +
                         ") is not a rotation (a quaternion of norm 1; set "
                         "orientation_covariance[0] to -1 for none)");
      }
      // The yaw of any non-zero quaternion: the scale cancels in atan2.
      sample.heading_rad = std::atan2(2.0 * (w * z + x * y), w * w + x * x - y * y - z * z);
    }
    contents_.log.imu_samples.push_back(sample);
    contents_.first_ns = std::min(contents_.first_ns, stamp);
  }

  // The stamp and the scaled number of a scalar topic's message.
  std::pair<std::int64_t, double> Scalar(const ScalarTopic& t, const char* key, const Channel& c,
                                         const rosbag::MessageInstance& m) const {
    const auto leaves =
        io::ros1::DecodeFields(c.spec, bytes_.data(), bytes_.size(), {t.field, "header.stamp"});
    const auto it = leaves.find(t.field);
    if (it == leaves.end() || it->second.kind != io::ros1::Leaf::kNumber) {
      ThrowIoError(bag_name_, 0, std::string(key) + ".field",
                   "topic " + t.topic + " has no number '" + t.field +
                       "' (its fields: " + FieldsOf(c.spec, bytes_) + ")");
    }
    return std::make_pair(StampOf(leaves, m), it->second.number * t.scale);
  }

  const TopicsConfig& topics_;
  const std::map<std::string, Channel>& channels_;
  const std::map<std::string, std::string>& camera_of_topic_;
  const std::string& bag_name_;
  const fs::path& out_;
  std::vector<std::uint8_t> bytes_;
  BagContents contents_;
};

// Frame sets: each front image with the nearest image of every other camera
// within skew_ns, renamed to its time from first_ns; the images of no set
// removed. Returns images/index.csv.
std::string MakeFrameSets(std::map<std::string, std::vector<PendingImage>>& images,
                          std::int64_t skew_ns, std::int64_t first_ns, const fs::path& out,
                          ImportSummary* summary) {
  for (auto& [name, list] : images) {
    std::sort(list.begin(), list.end(),
              [](const PendingImage& a, const PendingImage& b) { return a.stamp_ns < b.stamp_ns; });
  }
  std::map<std::string, std::set<std::size_t>> taken;
  std::string index = "t_ns,camera,file\n";
  std::int64_t last_set_ns = -1;
  for (const PendingImage& reference : images["front"]) {
    std::map<std::string, std::size_t> chosen;
    for (const auto& [name, list] : images) {
      std::size_t best = list.size();
      std::int64_t best_dt = skew_ns + 1;
      const auto lower =
          std::lower_bound(list.begin(), list.end(), reference.stamp_ns - skew_ns,
                           [](const PendingImage& p, std::int64_t t) { return p.stamp_ns < t; });
      for (auto it = lower; it != list.end() && it->stamp_ns <= reference.stamp_ns + skew_ns;
           ++it) {
        const std::size_t i = static_cast<std::size_t>(it - list.begin());
        const std::int64_t dt = std::llabs(it->stamp_ns - reference.stamp_ns);
        if (dt < best_dt && !taken[name].contains(i)) best = i, best_dt = dt;
      }
      if (best == list.size()) break;
      chosen[name] = best;
    }
    const std::int64_t t_ns = reference.stamp_ns - first_ns;
    if (chosen.size() != images.size() || t_ns <= last_set_ns) continue;
    last_set_ns = t_ns;
    for (const std::string& name : camera::AllCameraNames()) {
      if (!chosen.contains(name)) continue;
      const PendingImage& image = images[name][chosen[name]];
      const std::string relative = "images/" + name + "/" + std::to_string(t_ns) + image.extension;
      fs::rename(image.file, out / relative);
      taken[name].insert(chosen[name]);
      index += std::to_string(t_ns) + "," + name + "," + relative + "\n";
    }
    ++summary->frame_sets;
  }
  for (const auto& [name, list] : images) {
    for (std::size_t i = 0; i < list.size(); ++i) {
      if (taken[name].contains(i)) continue;
      fs::remove(list[i].file);
      ++summary->images_unmatched;
    }
  }
  return index;
}

}  // namespace

TopicsConfig LoadTopicsConfig(const fs::path& path) {
  const io::yaml_util::YamlReader r(path.string(), true);
  const YAML::Node root =
      io::yaml_util::LoadYaml(io::ReadTextFile(path, io::kMaxYamlBytes), path.string());
  r.ExpectMap(root, "");
  r.CheckKeys(
      root, "",
      {"cameras", "imu", "wheel_speed", "steering", "rig", "max_set_skew_s", "vehicle", "sensors"});
  for (const char* key :
       {"cameras", "imu", "wheel_speed", "steering", "rig", "vehicle", "sensors"}) {
    if (!root[key]) r.Fail(root, key, "missing key");
  }
  TopicsConfig config;
  const YAML::Node cameras = root["cameras"];
  r.ExpectMap(cameras, "cameras");
  std::vector<std::string_view> names;
  for (const std::string& name : camera::AllCameraNames()) names.push_back(name);
  r.CheckKeys(cameras, "cameras", names);
  for (const std::string& name : camera::FisheyeCameraNames()) {
    if (!cameras[name]) r.Fail(cameras, "cameras." + name, "missing key (the top view needs it)");
  }
  for (const std::string& name : camera::AllCameraNames()) {
    if (!cameras[name]) continue;
    config.cameras[name] = r.String(cameras[name], "cameras." + name);
    for (const auto& [other, topic] : config.cameras) {
      if (other != name && topic == config.cameras[name]) {
        r.Fail(cameras[name], "cameras." + name,
               "topic " + topic + " is cameras." + other + "'s too (each camera needs its own)");
      }
    }
  }
  config.imu = r.String(root["imu"], "imu");
  config.wheel_speed = ReadScalarTopic(r, root["wheel_speed"], "wheel_speed");
  config.steering = ReadScalarTopic(r, root["steering"], "steering");
  config.rig = path.parent_path() / r.String(root["rig"], "rig");
  if (root["max_set_skew_s"]) {
    config.max_set_skew_s = r.DoubleIn(root["max_set_skew_s"], "max_set_skew_s", 0.0, 1.0, "s");
  }
  io::yaml_util::ReadVehicleNode(r, root["vehicle"], "vehicle", &config.vehicle);
  std::string error;
  if (!config.vehicle.IsValid(&error)) r.Fail(root["vehicle"], "", error);
  r.ExpectKeys(root["sensors"], "sensors", {"odometry"});
  io::yaml_util::ReadOdometrySpecNode(r, root["sensors"]["odometry"], "sensors.odometry",
                                      &config.odometry_spec);
  if (!config.odometry_spec.IsValid(&error)) r.Fail(root["sensors"], "", error);
  return config;
}

ImportSummary ImportRosbag(const fs::path& bag_path, const TopicsConfig& topics,
                           const fs::path& out,
                           const std::function<void(std::size_t, std::size_t)>& progress) {
  const std::string bag_name = bag_path.string();
  const camera::CameraRig rig = io::LoadRig(topics.rig);
  for (const auto& [name, topic] : topics.cameras) {
    if (rig.Find(name) == nullptr) {
      ThrowIoError(topics.rig.string(), 0, "", "no camera '" + name + "' (topics.yaml has it)");
    }
  }
  // A FIFO or device in place of the bag would block the reader or never
  // end; a bag may be any size.
  io::CheckInputFile(bag_path, std::numeric_limits<std::uintmax_t>::max());
  rosbag::Bag bag;
  try {
    bag.open(bag_name, rosbag::bagmode::Read);
  } catch (const std::exception& e) {
    ThrowIoError(bag_name, 0, "", std::string("not a readable ROS 1 bag: ") + e.what());
  }
  rosbag::View view(bag);

  const std::map<std::string, Channel> channels = ReadChannels(view, bag_name);
  std::map<std::string, std::string> camera_of_topic;
  for (const auto& [name, topic] : topics.cameras) {
    RequireTopic(channels, bag_name, topic, "cameras." + name,
                 {"sensor_msgs/Image", "sensor_msgs/CompressedImage"});
    const auto [it, added] = camera_of_topic.emplace(topic, name);
    if (!added) {
      ThrowIoError(
          bag_name, 0, "cameras." + name,
          "topic " + topic + " is cameras." + it->second + "'s too (each camera needs its own)");
    }
  }
  RequireTopic(channels, bag_name, topics.imu, "imu", {"sensor_msgs/Imu"});
  RequireTopic(channels, bag_name, topics.wheel_speed.topic, "wheel_speed.topic", {});
  RequireTopic(channels, bag_name, topics.steering.topic, "steering.topic", {});

  fs::create_directories(out / "images");
  BagContents contents =
      MessageReader(topics, channels, camera_of_topic, bag_name, out).Read(view, progress);
  SensorLog& log = contents.log;
  const std::int64_t first_ns = contents.first_ns;
  if (log.wheel_speeds.empty() || log.steering_angles.empty() || log.imu_samples.empty()) {
    ThrowIoError(bag_name, 0, "", "no wheel speed, steering or IMU message on the topics given");
  }

  // Times from the first stamp on.
  ImportSummary summary;
  for (auto& s : log.wheel_speeds) s.t_ns -= first_ns;
  for (auto& s : log.steering_angles) s.t_ns -= first_ns;
  for (auto& s : log.imu_samples) s.t_ns -= first_ns;
  summary.duplicate_times = SortUnique(&log.wheel_speeds) + SortUnique(&log.steering_angles) +
                            SortUnique(&log.imu_samples);

  std::map<std::string, std::vector<PendingImage>>& images = contents.images;
  for (const auto& [name, topic] : topics.cameras) {
    if (images[name].empty()) ThrowIoError(bag_name, 0, "cameras." + name, "no image on " + topic);
  }
  const std::int64_t skew_ns = static_cast<std::int64_t>(std::llround(topics.max_set_skew_s * 1e9));
  const std::string index = MakeFrameSets(images, skew_ns, first_ns, out, &summary);
  io::WriteFileAtomically(out / "images/index.csv", index);
  io::WriteFileAtomically(out / "images/rig.yaml", io::ReadTextFile(topics.rig));

  io::Dataset dataset;
  dataset.name = bag_path.stem().string();
  dataset.created_by = "parkslam import-rosbag";
  dataset.vehicle = topics.vehicle;
  dataset.odometry_spec = topics.odometry_spec;
  dataset.log = std::move(log);
  summary.wheel_speeds = dataset.log.wheel_speeds.size();
  summary.steering_angles = dataset.log.steering_angles.size();
  summary.imu_samples = dataset.log.imu_samples.size();
  io::WriteDataset(out, dataset);
  return summary;
}

}  // namespace parkslam::rosbag_import
