#include "parkslam/camera/image_plane.h"

#include <algorithm>
#include <stdexcept>

namespace parkslam::camera {

ImagePlane ToImagePlane(const cv::Mat& grey) {
  if (grey.type() != CV_8UC1)
    throw std::invalid_argument("image plane: expected an 8-bit grey image");
  auto pixels = std::make_shared<std::vector<std::uint8_t>>(grey.total());
  for (int r = 0; r < grey.rows; ++r) {
    std::copy(grey.ptr<std::uint8_t>(r), grey.ptr<std::uint8_t>(r) + grey.cols,
              pixels->begin() + static_cast<long>(r) * grey.cols);
  }
  return {grey.cols, grey.rows, std::move(pixels)};
}

cv::Mat AsMat(const ImagePlane& plane) {
  return cv::Mat(plane.height, plane.width, CV_8UC1,
                 const_cast<std::uint8_t*>(plane.pixels->data()));
}

}  // namespace parkslam::camera
