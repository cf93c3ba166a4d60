#ifndef PARKSLAM_IO_IO_ERROR_H_
#define PARKSLAM_IO_IO_ERROR_H_

#include <stdexcept>
#include <string>
#include <string_view>

namespace parkslam::io {

// Every failure to read or write a file of the project. The message names
// the file and, where they apply, the line and the field:
//   "d/sensors/imu.csv:12: heading_rad: not a finite number"
//   "map.json: slots[3].corners: expected 4 points"
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "file:line: field: what", leaving out the line when line <= 0 and the field
// when it is empty.
std::string ErrorMessage(std::string_view file, int line, std::string_view field,
                         std::string_view what);

[[noreturn]] void ThrowIoError(std::string_view file, int line, std::string_view field,
                               std::string_view what);

}  // namespace parkslam::io

#endif  // PARKSLAM_IO_IO_ERROR_H_
