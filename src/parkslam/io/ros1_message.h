#ifndef PARKSLAM_IO_ROS1_MESSAGE_H_
#define PARKSLAM_IO_ROS1_MESSAGE_H_

// ROS 1 messages without their generated headers: the message definition a
// bag stores with each connection (the `.msg` text of the type and of every
// type it uses, sections separated by a line of '=' and headed
// "MSG: package/Type") is parsed once, and serialized messages are walked
// field by field (little-endian; strings and variable arrays prefixed by a
// uint32 length). So `import-rosbag` reads sensor_msgs/Image, Imu, and any
// topic whose field the user names ("twist.twist.linear.x").

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace parkslam::io::ros1 {

struct Field {
  std::string type;  // a primitive ("float64", "time") or "package/Type"
  std::string name;
  bool is_array = false;
  int fixed_length = -1;  // for T[N]; -1 for T[]
};

struct MessageSpec {
  std::string root;                                 // "sensor_msgs/Imu"
  std::map<std::string, std::vector<Field>> types;  // every type used
};

// Throws std::invalid_argument naming the type and the line for a field it
// cannot read or a type the definition does not define.
MessageSpec ParseDefinition(const std::string& root_type, std::string_view definition);

// One value of a decoded message. Numbers (every numeric primitive, and
// time / duration as seconds with `ns` exact) or text (string), or the bytes
// of a uint8[] / byte[] / char[] field, which point into the message.
struct Leaf {
  std::string path;  // "header.stamp", "orientation.w", "data", "ranges[3]"
  enum Kind { kNumber, kText, kBytes } kind = kNumber;
  double number = 0.0;
  std::int64_t ns = 0;  // time and duration: exact nanoseconds
  std::string text;
  const std::uint8_t* bytes = nullptr;
  std::size_t size = 0;
};

// Walks one serialized message and calls `visit` for every leaf. Throws
// std::invalid_argument when the bytes end early or are left over.
void Decode(const MessageSpec& spec, const std::uint8_t* data, std::size_t size,
            const std::function<void(const Leaf&)>& visit);

// The leaves at `paths`, by path; a path the message lacks is absent.
std::map<std::string, Leaf> DecodeFields(const MessageSpec& spec, const std::uint8_t* data,
                                         std::size_t size, const std::vector<std::string>& paths);

}  // namespace parkslam::io::ros1

#endif  // PARKSLAM_IO_ROS1_MESSAGE_H_
