#ifndef PARKSLAM_IO_TUM_H_
#define PARKSLAM_IO_TUM_H_

// Trajectories in the TUM RGB-D format, one pose a line:
//   t x y z qx qy qz qw
// t in seconds, position in metres, orientation as a unit quaternion; lines
// starting with '#' are comments. A planar pose is written with z = 0 and a
// rotation about z (DESIGN.md 3), and read back as the heading of the full
// rotation, so that files of 3D tools can be read too.

#include <filesystem>
#include <string>
#include <string_view>

#include "parkslam/common/trajectory.h"

namespace parkslam::io {

// The text of a TUM file: a comment line, then one line per pose with 9
// decimals for t (exact for integer nanoseconds), 6 for positions and 10 for
// the quaternion (heading within 2e-10 rad).
std::string FormatTum(const Trajectory& trajectory);

// Parses TUM text. `source_name` names the text in error messages. Throws
// IoError ("traj.tum:7: qz: not a finite number") for a wrong column count,
// a field that is not a finite number, a zero quaternion, timestamps that do
// not strictly increase, or no pose at all.
Trajectory ParseTum(std::string_view text, const std::string& source_name);

// Writes atomically. Throws IoError when a pose is not finite or the
// timestamps do not strictly increase (ReadTum would reject the file).
void WriteTum(const std::filesystem::path& path, const Trajectory& trajectory);

Trajectory ReadTum(const std::filesystem::path& path);

}  // namespace parkslam::io

#endif  // PARKSLAM_IO_TUM_H_
