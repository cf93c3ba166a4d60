#ifndef PARKSLAM_ROSBAG_ROS1_WRITER_H_
#define PARKSLAM_ROSBAG_ROS1_WRITER_H_

// Writing ROS 1 messages without their generated headers: a RawMessage
// carries its type, MD5 sum, definition and serialized bytes, and the
// message traits below let rosbag_storage write it like any message. The
// builders serialize the few types parkslam exchanges (little-endian, as
// ROS 1 does).

#include <ros/message_traits.h>
#include <ros/serialization.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

// A serialized message of any type (rosbag_storage alone, no generated
// message headers).
struct RawMessage {
  std::string type, md5, definition;
  std::vector<std::uint8_t> bytes;
};

namespace ros::message_traits {
template <>
struct MD5Sum<RawMessage> {
  static const char* value(const RawMessage& m) { return m.md5.c_str(); }
  static const char* value() { return "*"; }
};
template <>
struct DataType<RawMessage> {
  static const char* value(const RawMessage& m) { return m.type.c_str(); }
  static const char* value() { return "*"; }
};
template <>
struct Definition<RawMessage> {
  static const char* value(const RawMessage& m) { return m.definition.c_str(); }
};
}  // namespace ros::message_traits

namespace ros::serialization {
template <>
struct Serializer<RawMessage> {
  template <typename Stream>
  static void write(Stream& stream, const RawMessage& m) {
    std::memcpy(stream.advance(static_cast<std::uint32_t>(m.bytes.size())), m.bytes.data(),
                m.bytes.size());
  }
  static std::uint32_t serializedLength(const RawMessage& m) {
    return static_cast<std::uint32_t>(m.bytes.size());
  }
};
}  // namespace ros::serialization

namespace parkslam::rosbag_import {

inline constexpr const char* kHeaderDef =
    "================================================================================\n"
    "MSG: std_msgs/Header\nuint32 seq\ntime stamp\nstring frame_id\n";

// Little-endian ROS 1 serialization.
struct Writer {
  std::vector<std::uint8_t> bytes;
  template <typename T>
  void Put(T value) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(&value);
    bytes.insert(bytes.end(), p, p + sizeof(T));
  }
  void String(const std::string& s) {
    Put<std::uint32_t>(static_cast<std::uint32_t>(s.size()));
    bytes.insert(bytes.end(), s.begin(), s.end());
  }
  void Header(std::int64_t stamp_ns) {
    Put<std::uint32_t>(0);
    Put<std::uint32_t>(static_cast<std::uint32_t>(stamp_ns / 1'000'000'000));
    Put<std::uint32_t>(static_cast<std::uint32_t>(stamp_ns % 1'000'000'000));
    String("base_link");
  }
};

inline RawMessage Float64(double value) {
  Writer w;
  w.Put(value);
  return {"std_msgs/Float64", "fdb28210bfa9d7c91146260178d9a584", "float64 data\n", w.bytes};
}

// A geometry_msgs/TwistStamped with only linear.x set.
inline RawMessage SpeedStamped(std::int64_t stamp_ns, double speed) {
  Writer w;
  w.Header(stamp_ns);
  for (double v : {speed, 0.0, 0.0, 0.0, 0.0, 0.0}) w.Put(v);
  return {"geometry_msgs/TwistStamped", "98d34b0043a2093cf9d9345ab6eef12e",
          std::string("Header header\nTwist twist\n") + kHeaderDef +
              "================================================================================\n"
              "MSG: geometry_msgs/Twist\nVector3 linear\nVector3 angular\n"
              "================================================================================\n"
              "MSG: geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z\n",
          w.bytes};
}

// Without a heading (a gyro-only IMU) the orientation is the identity and
// orientation_covariance[0] is -1, sensor_msgs/Imu's "no orientation".
inline RawMessage Imu(std::int64_t stamp_ns, std::optional<double> yaw_rad, double yaw_rate) {
  Writer w;
  w.Header(stamp_ns);
  const double yaw = yaw_rad.value_or(0.0);
  for (double v : {0.0, 0.0, std::sin(yaw / 2), std::cos(yaw / 2)}) w.Put(v);
  w.Put(yaw_rad ? 0.0 : -1.0);
  for (int i = 1; i < 9; ++i) w.Put(0.0);
  for (double v : {0.0, 0.0, yaw_rate}) w.Put(v);
  for (int i = 0; i < 9; ++i) w.Put(0.0);
  for (double v : {0.0, 0.0, 9.81}) w.Put(v);
  for (int i = 0; i < 9; ++i) w.Put(0.0);
  return {"sensor_msgs/Imu", "6a62c6daae103f4ff57a132d6f95cec2",
          std::string("Header header\ngeometry_msgs/Quaternion orientation\n"
                      "float64[9] orientation_covariance\ngeometry_msgs/Vector3 angular_velocity\n"
                      "float64[9] angular_velocity_covariance\n"
                      "geometry_msgs/Vector3 linear_acceleration\n"
                      "float64[9] linear_acceleration_covariance\n") +
              kHeaderDef +
              "================================================================================\n"
              "MSG: geometry_msgs/Quaternion\nfloat64 x\nfloat64 y\nfloat64 z\nfloat64 w\n"
              "================================================================================\n"
              "MSG: geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z\n",
          w.bytes};
}

// A sensor_msgs/CompressedImage of already encoded bytes ("jpeg", "png").
inline RawMessage Compressed(std::int64_t stamp_ns, const std::string& format,
                             const std::vector<std::uint8_t>& encoded) {
  Writer w;
  w.Header(stamp_ns);
  w.String(format);
  w.Put<std::uint32_t>(static_cast<std::uint32_t>(encoded.size()));
  w.bytes.insert(w.bytes.end(), encoded.begin(), encoded.end());
  return {"sensor_msgs/CompressedImage", "8f7a12909da2c9d3332d540a0977563f",
          std::string("Header header\nstring format\nuint8[] data\n") + kHeaderDef, w.bytes};
}

// A sensor_msgs/Image, mono8, of width x height bytes.
inline RawMessage Mono8(std::int64_t stamp_ns, int width, int height, const std::uint8_t* pixels) {
  Writer w;
  w.Header(stamp_ns);
  w.Put<std::uint32_t>(static_cast<std::uint32_t>(height));
  w.Put<std::uint32_t>(static_cast<std::uint32_t>(width));
  w.String("mono8");
  w.Put<std::uint8_t>(0);
  w.Put<std::uint32_t>(static_cast<std::uint32_t>(width));
  const std::size_t size = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  w.Put<std::uint32_t>(static_cast<std::uint32_t>(size));
  w.bytes.insert(w.bytes.end(), pixels, pixels + size);
  return {"sensor_msgs/Image", "060021388200f6f0f447d0fcd9c64743",
          std::string("Header header\nuint32 height\nuint32 width\nstring encoding\n"
                      "uint8 is_bigendian\nuint32 step\nuint8[] data\n") +
              kHeaderDef,
          w.bytes};
}

}  // namespace parkslam::rosbag_import

#endif  // PARKSLAM_ROSBAG_ROS1_WRITER_H_
