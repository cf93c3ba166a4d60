#include "parkslam/io/ros1_message.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace parkslam::io::ros1 {
namespace {

using ::testing::HasSubstr;

constexpr const char* kDefinition =
    "# a comment\n"
    "Header header\n"
    "int8 MODE_A=1   # a constant, not a field\n"
    "float32[2] pair\n"
    "Point[] points\n"
    "uint8[] data\n"
    "================================================================================\n"
    "MSG: std_msgs/Header\n"
    "uint32 seq\ntime stamp\nstring frame_id\n"
    "================================================================================\n"
    "MSG: my_msgs/Point\n"
    "float64 x\nint16 y\n";

struct Bytes {
  std::vector<std::uint8_t> v;
  template <typename T>
  Bytes& Put(T value) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(&value);
    v.insert(v.end(), p, p + sizeof(T));
    return *this;
  }
};

std::vector<std::uint8_t> Sample() {
  Bytes b;
  b.Put<std::uint32_t>(7).Put<std::uint32_t>(12).Put<std::uint32_t>(500'000'000);
  b.Put<std::uint32_t>(4);
  for (char c : std::string("odom")) b.Put(c);
  b.Put<float>(1.5f).Put<float>(-2.0f);
  b.Put<std::uint32_t>(2)
      .Put<double>(3.25)
      .Put<std::int16_t>(-4)
      .Put<double>(5.0)
      .Put<std::int16_t>(6);
  b.Put<std::uint32_t>(3).Put<std::uint8_t>(9).Put<std::uint8_t>(8).Put<std::uint8_t>(7);
  return b.v;
}

TEST(Ros1MessageTest, DecodesNestedFieldsArraysStringsAndTime) {
  const MessageSpec spec = ParseDefinition("my_msgs/Sample", kDefinition);
  EXPECT_EQ(spec.types.at("my_msgs/Sample").size(), 4u);  // the constant is no field
  EXPECT_EQ(spec.types.at("my_msgs/Sample")[2].type, "my_msgs/Point");
  const std::vector<std::uint8_t> bytes = Sample();
  const auto f = DecodeFields(spec, bytes.data(), bytes.size(),
                              {"header.seq", "header.stamp", "header.frame_id", "pair[1]",
                               "points[0].x", "points[1].y", "data"});
  EXPECT_EQ(f.at("header.seq").number, 7.0);
  EXPECT_EQ(f.at("header.stamp").ns, 12'500'000'000);
  EXPECT_DOUBLE_EQ(f.at("header.stamp").number, 12.5);
  EXPECT_EQ(f.at("header.frame_id").text, "odom");
  EXPECT_EQ(f.at("pair[1]").number, -2.0);
  EXPECT_EQ(f.at("points[0].x").number, 3.25);
  EXPECT_EQ(f.at("points[1].y").number, 6.0);
  ASSERT_EQ(f.at("data").size, 3u);
  EXPECT_EQ(f.at("data").bytes[2], 7);
}

TEST(Ros1MessageTest, TruncatedLeftOverAndCorruptDataAreErrors) {
  const MessageSpec spec = ParseDefinition("my_msgs/Sample", kDefinition);
  std::vector<std::uint8_t> bytes = Sample();
  auto error = [&](const std::vector<std::uint8_t>& b) {
    try {
      Decode(spec, b.data(), b.size(), [](const Leaf&) {});
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error(bytes), "");
  EXPECT_EQ(error(std::vector<std::uint8_t>(bytes.begin(), bytes.end() - 1)),
            "ros1: the message ends early");
  std::vector<std::uint8_t> longer = bytes;
  longer.push_back(0);
  EXPECT_EQ(error(longer), "ros1: 1 bytes left over after the message");
  std::vector<std::uint8_t> huge = bytes;
  const std::uint32_t count = 0xffffffffu;  // the points array's length
  std::memcpy(huge.data() + 12 + 4 + 4 + 8, &count, 4);
  EXPECT_EQ(error(huge), "ros1: array longer than the data");
}

TEST(Ros1MessageTest, UndefinedTypesAreNamed) {
  EXPECT_THAT(
      [] {
        try {
          ParseDefinition("a/B", "Missing m\n");
        } catch (const std::invalid_argument& e) {
          return std::string(e.what());
        }
        return std::string();
      }(),
      HasSubstr("a/B.m: no definition of a/Missing"));
}

}  // namespace
}  // namespace parkslam::io::ros1
