#ifndef PARKSLAM_ROS_MAP_MARKERS_H_
#define PARKSLAM_ROS_MAP_MARKERS_H_

// The map as rviz and Foxglove draw it (visualization_msgs/MarkerArray):
// each slot as a closed line through its four corners (white where every
// corner was seen, orange where some corner is the standard depth's guess,
// grey for a slot under a temporary ID), its ID as text at its centre, and
// each tag as an arrow along its outward normal with its number. The first
// marker deletes every marker before, so that a map that grew or changed
// replaces the old one whole. C++17, as the node's ROS part
// (live_bridge.h).

#include <visualization_msgs/MarkerArray.h>

#include <string>

#include "live_bridge.h"

namespace parkslam::ros_node {

visualization_msgs::MarkerArray MapMarkers(const BridgeMap& map, const std::string& frame_id,
                                           const ros::Time& stamp);

}  // namespace parkslam::ros_node

#endif  // PARKSLAM_ROS_MAP_MARKERS_H_
