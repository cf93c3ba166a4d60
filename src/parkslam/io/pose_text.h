#ifndef PARKSLAM_IO_POSE_TEXT_H_
#define PARKSLAM_IO_POSE_TEXT_H_

// A pose written as text, "x,y,yaw" (metres, metres, radians): a start
// pose given on a command line (`--init`) or as a node's parameter.

#include <string>

#include "parkslam/common/se2.h"

namespace parkslam::io {

// Parses "x,y,yaw", every part a whole finite number within the limits of
// common/plausible_ranges.h. Throws std::invalid_argument naming `name`
// ("--init: expected x,y,yaw (metres, radians), got '1,2'").
SE2 ParsePose(const std::string& text, const std::string& name);

}  // namespace parkslam::io

#endif  // PARKSLAM_IO_POSE_TEXT_H_
