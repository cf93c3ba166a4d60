#include "map_markers.h"

#include <gtest/gtest.h>

#include <cmath>

namespace parkslam::ros_node {
namespace {

BridgeMap TwoSlotsOneTag() {
  BridgeMap map;
  BridgeMap::Slot seen;
  seen.id = "12";
  seen.corners_m = {{{0, 0}, {2.5, 0}, {2.5, 5.3}, {0, 5.3}}};
  seen.corner_observed = {true, true, true, true};
  BridgeMap::Slot guessed = seen;
  guessed.id = "t3";
  guessed.temporary = true;
  guessed.corner_observed = {true, true, false, false};
  for (auto& c : guessed.corners_m) c[0] += 3.0;
  map.slots = {seen, guessed};
  map.tags = {{7, 4.0, -1.0, M_PI / 2.0}};
  return map;
}

TEST(MapMarkersTest, EachSlotIsAClosedLineWithItsIdAndEachTagAnArrow) {
  const visualization_msgs::MarkerArray a =
      MapMarkers(TwoSlotsOneTag(), "map", ros::Time(1700000000, 0));
  // Delete-all, two slot lines with two IDs, one arrow and its number.
  ASSERT_EQ(a.markers.size(), 7u);
  EXPECT_EQ(a.markers[0].action, visualization_msgs::Marker::DELETEALL);
  const visualization_msgs::Marker& line = a.markers[1];
  EXPECT_EQ(line.type, visualization_msgs::Marker::LINE_STRIP);
  EXPECT_EQ(line.header.frame_id, "map");
  ASSERT_EQ(line.points.size(), 5u);
  EXPECT_DOUBLE_EQ(line.points[4].x, line.points[0].x);  // closed
  EXPECT_DOUBLE_EQ(line.points[2].y, 5.3);
  EXPECT_EQ(a.markers[2].text, "12");
  EXPECT_DOUBLE_EQ(a.markers[2].pose.position.x, 1.25);  // at the slot's centre
  // Under a temporary ID: grey; a seen slot: white.
  EXPECT_FLOAT_EQ(line.color.b, 1.0f);
  EXPECT_FLOAT_EQ(a.markers[3].color.r, 0.6f);
  EXPECT_EQ(a.markers[4].text, "t3");
  const visualization_msgs::Marker& arrow = a.markers[5];
  EXPECT_EQ(arrow.type, visualization_msgs::Marker::ARROW);
  EXPECT_NEAR(2.0 * std::atan2(arrow.pose.orientation.z, arrow.pose.orientation.w), M_PI / 2.0,
              1e-12);
  EXPECT_EQ(a.markers[6].text, "tag 7");
  // Markers of one namespace have ids of their own.
  EXPECT_NE(a.markers[1].id, a.markers[3].id);
}

TEST(MapMarkersTest, AnEmptyMapOnlyClearsTheOldOne) {
  const visualization_msgs::MarkerArray a = MapMarkers(BridgeMap{}, "map", ros::Time(1, 0));
  ASSERT_EQ(a.markers.size(), 1u);
  EXPECT_EQ(a.markers[0].action, visualization_msgs::Marker::DELETEALL);
}

}  // namespace
}  // namespace parkslam::ros_node
