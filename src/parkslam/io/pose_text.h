#ifndef PARKSLAM_IO_POSE_TEXT_H_
#define PARKSLAM_IO_POSE_TEXT_H_

// A pose written as text, "x,y,yaw" (metres, metres, radians), or the
// map's "entrance": a start pose given on a command line (`--init`) or as
// a node's parameter.

#include <string>

#include "parkslam/common/se2.h"
#include "parkslam/map/semantic_map.h"

namespace parkslam::io {

// Parses "x,y,yaw", every part a whole finite number within the limits of
// common/plausible_ranges.h. Throws std::invalid_argument naming `name`
// ("--init: expected x,y,yaw (metres, radians), got '1,2'").
SE2 ParsePose(const std::string& text, const std::string& name);

// A start pose on `map`: "entrance" (where the map's own drive began,
// SemanticMap::entrance) or "x,y,yaw" as ParsePose. Throws
// std::invalid_argument naming `name` and `map_name` for a map without an
// entrance.
SE2 ParseStartPose(const std::string& text, const SemanticMap& map, const std::string& name,
                   const std::string& map_name);

}  // namespace parkslam::io

#endif  // PARKSLAM_IO_POSE_TEXT_H_
