#include "image_files.h"

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "parkslam/io/atomic_file.h"
#include "parkslam/io/image_header.h"

namespace parkslam::app {

cv::Mat ReadImage(const std::string& path, int flags) {
  if (!std::filesystem::exists(path)) throw std::runtime_error(path + ": no such file");
  io::CheckImageSize(path);
  const cv::Mat image = cv::imread(path, flags);
  if (image.empty()) throw std::runtime_error(path + ": not a readable image");
  return image;
}

void WriteImage(const std::string& path, const cv::Mat& image) {
  std::vector<uchar> buffer;
  const std::string ext = std::filesystem::path(path).extension().string();
  bool encoded = false;
  try {
    encoded = cv::imencode(ext.empty() ? ".png" : ext, image, buffer);
  } catch (const cv::Exception&) {
    // OpenCV throws for an extension it has no encoder for.
  }
  if (!encoded) {
    throw std::runtime_error(path + ": cannot write an image as '" + ext +
                             "' (give a .png or .jpg file)");
  }
  io::WriteFileAtomically(
      path, std::string_view(reinterpret_cast<const char*>(buffer.data()), buffer.size()));
}

}  // namespace parkslam::app
