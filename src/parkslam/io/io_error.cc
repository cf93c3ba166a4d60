#include "parkslam/io/io_error.h"

namespace parkslam::io {

std::string ErrorMessage(std::string_view file, int line, std::string_view field,
                         std::string_view what) {
  std::string message(file);
  if (line > 0) {
    message += ':';
    message += std::to_string(line);
  }
  message += ": ";
  if (!field.empty()) {
    message += field;
    message += ": ";
  }
  message += what;
  return message;
}

void ThrowIoError(std::string_view file, int line, std::string_view field, std::string_view what) {
  throw IoError(ErrorMessage(file, line, field, what));
}

}  // namespace parkslam::io
