#include "live_bridge.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <limits>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "parkslam/camera/image_plane.h"
#include "parkslam/common/percentile.h"
#include "parkslam/io/map_json.h"
#include "parkslam/io/options_yaml.h"
#include "parkslam/io/pose_text.h"
#include "parkslam/io/rig_yaml.h"
#include "parkslam/io/ros1_message.h"
#include "parkslam/live/frame_set_assembler.h"
#include "parkslam/live/live_system.h"
#include "parkslam/mapping/map_update.h"
#include "parkslam/odometry/odometry_ekf.h"
#include "parkslam/rosbag/rosbag_import.h"

namespace parkslam::ros_node {
namespace {

constexpr std::int64_t kUnset = std::numeric_limits<std::int64_t>::min();

}  // namespace

struct LiveBridge::Impl {
  BridgeOptions options;
  rosbag_import::TopicsConfig topics;
  std::vector<std::pair<std::string, std::string>> cameras;
  camera::CameraRig rig;
  SemanticMap map;  // localizing
  std::optional<live::FrameSetAssembler> sets;
  std::unique_ptr<live::LiveSystem> system;
  std::function<void(const BridgePose&)> on_pose;
  // Set by the caller's thread at the first message, before any estimate;
  // read by the perception's.
  std::atomic<std::int64_t> t0_ns{kUnset};
  std::map<std::string, io::ros1::MessageSpec> specs;  // by data type
  std::int64_t last_pose_ns = kUnset;
  // With an estimate while tracking; counted by whichever thread made the
  // estimate, read by the caller's.
  std::atomic<int> frames_tracked{0};

  TimeNs ToDrive(std::int64_t stamp_ns) {
    std::int64_t unset = kUnset;
    t0_ns.compare_exchange_strong(unset, stamp_ns);
    return stamp_ns - t0_ns.load();
  }
  std::int64_t ToStamp(TimeNs t_ns) const {
    const std::int64_t t0 = t0_ns.load();
    return t_ns + (t0 == kUnset ? 0 : t0);
  }

  BridgePose Pose(TimeNs t_ns, const SE2& T_map_vehicle) const {
    BridgePose p;
    p.t_ns = ToStamp(t_ns);
    p.x_m = T_map_vehicle.translation().x();
    p.y_m = T_map_vehicle.translation().y();
    p.yaw_rad = T_map_vehicle.yaw();
    return p;
  }

  // Every estimate once the car was first localized: tracking, or lost
  // (the dead reckoning from the last fix, its covariance growing).
  void OnEstimate(const localization::LocalizationEstimate& e) {
    if (e.state == localization::LocalizerState::kUninitialized || !on_pose) return;
    BridgePose p = Pose(e.t_ns, e.T_map_vehicle);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) p.covariance[3 * r + c] = e.covariance(r, c);
    }
    p.second = last_pose_ns == e.t_ns;
    p.tracking = e.state == localization::LocalizerState::kTracking;
    p.slots_used = e.slots.used;
    p.tags_used = e.tags.used;
    if (!p.second && p.tracking) ++frames_tracked;
    last_pose_ns = e.t_ns;
    on_pose(p);
  }

  bool Feed(const std::string& camera, std::int64_t stamp_ns, const cv::Mat& grey) {
    if (grey.empty()) throw std::runtime_error(camera + ": the image does not decode");
    const camera::CameraConfig* config = rig.Find(camera);
    if (config == nullptr) throw std::runtime_error(camera + ": not a camera of the rig");
    if (grey.cols != config->intrinsics.width || grey.rows != config->intrinsics.height) {
      throw std::runtime_error(camera + ": an image of " + std::to_string(grey.cols) + " x " +
                               std::to_string(grey.rows) + ", and the rig's camera has " +
                               std::to_string(config->intrinsics.width) + " x " +
                               std::to_string(config->intrinsics.height));
    }
    bool fed = false;
    for (CameraFrame& frame : sets->Add(camera, ToDrive(stamp_ns), camera::ToImagePlane(grey))) {
      system->Process(std::move(frame));
      fed = true;
    }
    return fed;
  }
};

LiveBridge::LiveBridge(const BridgeOptions& options, std::function<void(const BridgePose&)> on_pose)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.options = options;
  m.on_pose = std::move(on_pose);
  m.topics = rosbag_import::LoadTopicsConfig(options.topics);
  m.rig = io::LoadRig(options.rig.empty() ? m.topics.rig : std::filesystem::path(options.rig));
  std::vector<std::string> names;
  for (const auto& [name, topic] : m.topics.cameras) {
    if (m.rig.Find(name) == nullptr) {
      throw std::runtime_error(options.topics + ": cameras." + name +
                               ": the rig has no such camera");
    }
    m.cameras.emplace_back(name, topic);
  }
  // The front camera first: it is the reference of a frame set, as in
  // import-rosbag.
  std::stable_partition(m.cameras.begin(), m.cameras.end(),
                        [](const auto& c) { return c.first == "front"; });
  for (const auto& [name, topic] : m.cameras) names.push_back(name);
  m.sets.emplace(names, static_cast<TimeNs>(std::llround(m.topics.max_set_skew_s * 1e9)));

  const AlgorithmOptions algorithm =
      options.options.empty() ? AlgorithmOptions{} : io::LoadOptionsFile(options.options);
  live::LiveOptions live;
  live.perception = algorithm.front_end;
  live.localizer = algorithm.localizer;
  live.mapper = algorithm.mapper;
  live.odometry = odometry::EkfOptionsFromSpec(m.topics.odometry_spec, m.topics.vehicle);
  live.wait_for_perception = options.wait_for_perception;
  // Each camera and each sensor has a topic, and so a connection, of its
  // own: a frame set is complete at its last image, which may come after
  // odometry newer than the set; the estimator takes the odometry a
  // quarter of a second late (or as soon as a frame after it needs it).
  live.reorder_window_s = 0.25;
  // The stored map: to localize on, or to update from this drive
  // (mapping/map_update.h). ~init may name its entrance.
  if (!options.mapping || !options.map.empty()) m.map = io::ReadMap(options.map);
  std::optional<SE2> start;
  if (!options.init.empty()) {
    try {
      start = io::ParseStartPose(options.init, m.map, "~init",
                                 options.map.empty() ? "the new map" : options.map);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(e.what());
    }
  }
  if (options.mapping) {
    m.system = std::make_unique<live::LiveSystem>(&m.rig, live, start);
  } else {
    live.on_estimate = [&m](const localization::LocalizationEstimate& e) { m.OnEstimate(e); };
    const Eigen::Vector3d sigma = options.init == "entrance" ? live.localizer.EntranceSigmas()
                                                             : Eigen::Vector3d(0.5, 0.5, 0.1);
    m.system = std::make_unique<live::LiveSystem>(m.map, &m.rig, live, start, sigma);
  }
}

LiveBridge::~LiveBridge() = default;

const std::vector<std::pair<std::string, std::string>>& LiveBridge::cameras() const {
  return impl_->cameras;
}
std::string LiveBridge::imu_topic() const { return impl_->topics.imu; }
BridgeScalarTopic LiveBridge::wheel_speed() const {
  return {impl_->topics.wheel_speed.topic, impl_->topics.wheel_speed.field};
}
BridgeScalarTopic LiveBridge::steering() const {
  return {impl_->topics.steering.topic, impl_->topics.steering.field};
}

std::string LiveBridge::Describe() const {
  const Impl& m = *impl_;
  std::string s = m.options.mapping ? "mapping" : "localizing on " + m.options.map;
  if (!m.options.map.empty()) {
    s += (m.options.mapping ? ", to update " + m.options.map : std::string()) + " (" +
         std::to_string(m.map.slots.size()) + " slots, " + std::to_string(m.map.tags.size()) +
         " tags)";
  }
  s += "; cameras";
  for (const auto& [name, topic] : m.cameras) s += " " + name + " (" + topic + ")";
  s += "; IMU " + m.topics.imu + "; wheel speed " + m.topics.wheel_speed.topic + "." +
       m.topics.wheel_speed.field + "; steering " + m.topics.steering.topic + "." +
       m.topics.steering.field;
  return s;
}

bool LiveBridge::CompressedImage(const std::string& camera, std::int64_t t_ns,
                                 const std::uint8_t* data, std::size_t size) {
  const cv::Mat bytes(1, static_cast<int>(size), CV_8UC1, const_cast<std::uint8_t*>(data));
  // As io's image folders read a recording's JPEG and PNG files.
  return impl_->Feed(camera, t_ns, cv::imdecode(bytes, cv::IMREAD_GRAYSCALE));
}

bool LiveBridge::RawImage(const std::string& camera, std::int64_t t_ns, const std::string& encoding,
                          int width, int height, std::size_t step, const std::uint8_t* data,
                          std::size_t size) {
  const int channels = encoding == "mono8" ? 1 : encoding == "rgb8" || encoding == "bgr8" ? 3 : 0;
  if (channels == 0) {
    throw std::runtime_error(camera + ": encoding '" + encoding +
                             "' (mono8, rgb8 and bgr8 are taken)");
  }
  if (width <= 0 || height <= 0 || step < static_cast<std::size_t>(width * channels) ||
      size < step * static_cast<std::size_t>(height)) {
    throw std::runtime_error(camera + ": an image of " + std::to_string(width) + " x " +
                             std::to_string(height) + " with step " + std::to_string(step) +
                             " needs more than its " + std::to_string(size) + " bytes");
  }
  const cv::Mat wrapped(height, width, channels == 1 ? CV_8UC1 : CV_8UC3,
                        const_cast<std::uint8_t*>(data), step);
  cv::Mat grey;
  if (channels == 1) {
    grey = wrapped.clone();
  } else {
    cv::cvtColor(wrapped, grey, encoding == "rgb8" ? cv::COLOR_RGB2GRAY : cv::COLOR_BGR2GRAY);
  }
  return impl_->Feed(camera, t_ns, grey);
}

void LiveBridge::Imu(std::int64_t t_ns, double yaw_rate_radps, std::optional<double> heading_rad) {
  impl_->system->Process(ImuSample{impl_->ToDrive(t_ns), yaw_rate_radps, heading_rad});
}

void LiveBridge::Scalar(bool wheel_speed, const std::string& datatype,
                        const std::string& definition, const std::uint8_t* data, std::size_t size,
                        std::int64_t stamp_if_none_ns) {
  Impl& m = *impl_;
  const rosbag_import::ScalarTopic& topic = wheel_speed ? m.topics.wheel_speed : m.topics.steering;
  auto spec = m.specs.find(datatype);
  if (spec == m.specs.end()) {
    try {
      spec = m.specs.emplace(datatype, io::ros1::ParseDefinition(datatype, definition)).first;
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(topic.topic + ": " + e.what());
    }
  }
  std::map<std::string, io::ros1::Leaf> leaves;
  try {
    leaves = io::ros1::DecodeFields(spec->second, data, size, {topic.field, "header.stamp"});
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(topic.topic + ": " + e.what());
  }
  const auto value = leaves.find(topic.field);
  if (value == leaves.end() || value->second.kind != io::ros1::Leaf::kNumber) {
    throw std::runtime_error(topic.topic + ": no number '" + topic.field + "' in " + datatype);
  }
  const auto stamp = leaves.find("header.stamp");
  const TimeNs t_ns = m.ToDrive(stamp != leaves.end() && stamp->second.ns > 0 ? stamp->second.ns
                                                                              : stamp_if_none_ns);
  const double v = value->second.number * topic.scale;
  if (wheel_speed) {
    m.system->Process(WheelSpeed{t_ns, v});
  } else {
    m.system->Process(SteeringAngle{t_ns, v});
  }
}

std::optional<BridgePose> LiveBridge::Predicted() const {
  const std::optional<TimedPose> pose = impl_->system->PredictedPose();
  if (!pose) return std::nullopt;
  return impl_->Pose(pose->t_ns, pose->T_map_vehicle);
}

BridgeMap LiveBridge::Map() const {
  const SemanticMap map = impl_->system->Map();
  BridgeMap out;
  for (const MapSlot& slot : map.slots) {
    BridgeMap::Slot s;
    s.id = slot.id;
    s.temporary = slot.temporary;
    for (int k = 0; k < kSlotCorners; ++k) {
      s.corners_m[k] = {slot.corners_map[k].x(), slot.corners_map[k].y()};
      s.corner_observed[k] = slot.corner_observed[k];
    }
    out.slots.push_back(s);
  }
  for (const MapTag& tag : map.tags) {
    out.tags.push_back({tag.tag_id, tag.p_map.x(), tag.p_map.y(), tag.yaw_map_rad});
  }
  return out;
}

std::string LiveBridge::SaveMap(const std::string& path) const {
  const Impl& m = *impl_;
  if (m.options.map.empty()) {
    io::WriteMap(path, m.system->Map());
    return "";
  }
  // The stored map updated from this drive's map as it stands.
  mapping::MapUpdateOptions update;
  update.label = m.options.label;
  if (update.label.empty()) {
    // The drive's first stamp, as a UTC date and time.
    const std::time_t first_s = static_cast<std::time_t>(m.t0_ns.load() / 1'000'000'000);
    std::tm utc{};
    gmtime_r(&first_s, &utc);
    char text[32];
    std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%SZ", &utc);
    update.label = text;
  }
  mapping::MapUpdateReport r;
  io::WriteMap(
      path, mapping::UpdateMap(m.map, m.system->Map(), m.system->KeyframeTrajectory(), update, &r));
  char line[300];
  std::snprintf(line, sizeof(line),
                "%s updated: slots %d confirmed, %d moved, %d repainted, %d added; tags %d "
                "confirmed, %d moved, %d added, %d removed",
                m.options.map.c_str(), r.slots_confirmed, r.slots_moved, r.slots_repainted,
                r.slots_added, r.tags_confirmed, r.tags_moved, r.tags_added, r.tags_removed);
  return line;
}

void LiveBridge::Finish() { impl_->system->Finish(); }

std::string LiveBridge::Summary() const {
  const live::LiveStats st = impl_->system->stats();
  const live::FrameSetStats& sets = impl_->sets->stats();
  char line[400];
  std::snprintf(line, sizeof(line),
                "%d frame sets (%d images in none, %d out of order), %d perceived, %d dropped; "
                "%d estimates, %d frames tracked; latency to a frame's first pose median %.2f ms, "
                "p99 %.2f ms",
                sets.sets, sets.images_unmatched, sets.images_out_of_order, st.frames_perceived,
                st.frames_dropped, st.estimates, impl_->frames_tracked.load(),
                Percentile(st.latency_ms, 0.5), Percentile(st.latency_ms, 0.99));
  return line;
}

}  // namespace parkslam::ros_node
