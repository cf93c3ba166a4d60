#include "map_markers.h"

#include <cmath>

namespace parkslam::ros_node {
namespace {

std_msgs::ColorRGBA Colour(float r, float g, float b) {
  std_msgs::ColorRGBA c;
  c.r = r, c.g = g, c.b = b, c.a = 1.0f;
  return c;
}

geometry_msgs::Point Point(double x, double y, double z) {
  geometry_msgs::Point q;
  q.x = x, q.y = y, q.z = z;
  return q;
}

visualization_msgs::Marker Base(const std::string& frame_id, const ros::Time& stamp, const char* ns,
                                int id, int type) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame_id;
  m.header.stamp = stamp;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  return m;
}

}  // namespace

visualization_msgs::MarkerArray MapMarkers(const BridgeMap& map, const std::string& frame_id,
                                           const ros::Time& stamp) {
  visualization_msgs::MarkerArray out;
  visualization_msgs::Marker clear = Base(frame_id, stamp, "", 0, 0);
  clear.action = visualization_msgs::Marker::DELETEALL;
  out.markers.push_back(clear);
  int id = 0;
  for (const BridgeMap::Slot& slot : map.slots) {
    visualization_msgs::Marker line =
        Base(frame_id, stamp, "slots", id, visualization_msgs::Marker::LINE_STRIP);
    line.scale.x = 0.08;
    bool all_seen = true;
    for (bool seen : slot.corner_observed) all_seen = all_seen && seen;
    line.color = slot.temporary ? Colour(0.6f, 0.6f, 0.6f)
                 : all_seen     ? Colour(1.0f, 1.0f, 1.0f)
                                : Colour(1.0f, 0.6f, 0.1f);
    double centre_x = 0.0, centre_y = 0.0;
    for (int k = 0; k <= 4; ++k) {
      const auto& c = slot.corners_m[k % 4];
      line.points.push_back(Point(c[0], c[1], 0.02));
    }
    for (const auto& c : slot.corners_m) centre_x += c[0] / 4.0, centre_y += c[1] / 4.0;
    out.markers.push_back(line);
    if (!slot.id.empty()) {
      visualization_msgs::Marker text =
          Base(frame_id, stamp, "slot_ids", id, visualization_msgs::Marker::TEXT_VIEW_FACING);
      text.pose.position = Point(centre_x, centre_y, 0.1);
      text.scale.z = 0.8;
      text.color = line.color;
      text.text = slot.id;
      out.markers.push_back(text);
    }
    ++id;
  }
  id = 0;
  for (const BridgeMap::Tag& tag : map.tags) {
    visualization_msgs::Marker arrow =
        Base(frame_id, stamp, "tags", id, visualization_msgs::Marker::ARROW);
    arrow.pose.position = Point(tag.x_m, tag.y_m, 1.0);
    arrow.pose.orientation.z = std::sin(tag.yaw_rad / 2.0);
    arrow.pose.orientation.w = std::cos(tag.yaw_rad / 2.0);
    arrow.scale.x = 0.6, arrow.scale.y = 0.12, arrow.scale.z = 0.12;
    arrow.color = Colour(0.2f, 0.5f, 1.0f);
    out.markers.push_back(arrow);
    visualization_msgs::Marker text =
        Base(frame_id, stamp, "tag_ids", id, visualization_msgs::Marker::TEXT_VIEW_FACING);
    text.pose.position = Point(tag.x_m, tag.y_m, 1.5);
    text.scale.z = 0.5;
    text.color = arrow.color;
    text.text = "tag " + std::to_string(tag.id);
    out.markers.push_back(text);
    ++id;
  }
  return out;
}

}  // namespace parkslam::ros_node
