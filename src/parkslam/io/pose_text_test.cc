#include "parkslam/io/pose_text.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <stdexcept>

namespace parkslam::io {
namespace {

using ::testing::HasSubstr;

std::string ErrorOf(const std::string& text, const SemanticMap& map) {
  try {
    ParseStartPose(text, map, "--init", "old.json");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(PoseTextTest, ReadsAPoseAndRefusesWhatIsNotOne) {
  const SE2 p = ParsePose("-8,12.5,0.25", "--init");
  EXPECT_DOUBLE_EQ(p.x(), -8.0);
  EXPECT_DOUBLE_EQ(p.y(), 12.5);
  EXPECT_DOUBLE_EQ(p.yaw(), 0.25);
  EXPECT_THROW(ParsePose("1,2", "--init"), std::invalid_argument);
  EXPECT_THROW(ParsePose("1,2,x", "--init"), std::invalid_argument);
  EXPECT_THROW(ParsePose("1e9,2,0", "--init"), std::invalid_argument);
}

// "entrance" is the map's own, where it has one; a pose stays a pose.
TEST(PoseTextTest, AStartIsTheMapsEntranceOrAPose) {
  SemanticMap map;
  EXPECT_THAT(ErrorOf("entrance", map), HasSubstr("--init entrance: old.json has no entrance"));
  map.entrance = SE2(-40.0, 9.1, 0.02);
  const SE2 start = ParseStartPose("entrance", map, "--init", "old.json");
  EXPECT_DOUBLE_EQ(start.x(), -40.0);
  EXPECT_DOUBLE_EQ(start.yaw(), 0.02);
  EXPECT_DOUBLE_EQ(ParseStartPose("1,2,3", map, "--init", "old.json").y(), 2.0);
  EXPECT_THAT(ErrorOf("entrence", map), HasSubstr("expected x,y,yaw"));
}

}  // namespace
}  // namespace parkslam::io
