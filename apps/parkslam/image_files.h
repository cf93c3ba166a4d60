#ifndef PARKSLAM_APPS_IMAGE_FILES_H_
#define PARKSLAM_APPS_IMAGE_FILES_H_

// Image files for the commands: reading with errors that name the file,
// writing atomically (a crash never leaves half an image).

#include <opencv2/core.hpp>
#include <string>

namespace parkslam::app {

// cv::imread with `flags`; throws std::runtime_error naming the file when
// it is missing or not an image.
cv::Mat ReadImage(const std::string& path, int flags);

// Encodes by the file's extension (PNG without one) and writes atomically.
void WriteImage(const std::string& path, const cv::Mat& image);

}  // namespace parkslam::app

#endif  // PARKSLAM_APPS_IMAGE_FILES_H_
