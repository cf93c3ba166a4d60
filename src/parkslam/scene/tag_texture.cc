#include "parkslam/scene/tag_texture.h"

#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>

#include <cstdlib>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>

namespace parkslam::scene {
namespace {

// The family is read-only once created; it lives as long as the program.
const apriltag_family_t* Family() {
  static const apriltag_family_t* const family = tag36h11_create();
  return family;
}

}  // namespace

int Tag36h11Count() { return static_cast<int>(Family()->ncodes); }

cv::Mat Tag36h11Image(int tag_id, int pixels_per_cell) {
  if (tag_id < 0 || tag_id >= Tag36h11Count()) {
    throw std::out_of_range("tag36h11 has no tag " + std::to_string(tag_id));
  }
  if (pixels_per_cell < 1) throw std::invalid_argument("pixels_per_cell must be at least 1");
  // apriltag_to_image does not modify the family; its C signature lacks const.
  image_u8_t* rendered = apriltag_to_image(const_cast<apriltag_family_t*>(Family()), tag_id);
  const cv::Mat view(rendered->height, rendered->width, CV_8UC1, rendered->buf,
                     static_cast<size_t>(rendered->stride));
  cv::Mat cells = view.clone();
  // image_u8_destroy is not exported by Debian's libapriltag 3.3; it frees
  // the buffer and the struct, both from calloc.
  std::free(rendered->buf);
  std::free(rendered);
  if (pixels_per_cell == 1) return cells;
  cv::Mat image;
  cv::resize(cells, image, cv::Size(), pixels_per_cell, pixels_per_cell, cv::INTER_NEAREST);
  return image;
}

}  // namespace parkslam::scene
