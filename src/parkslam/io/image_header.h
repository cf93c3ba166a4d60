#ifndef PARKSLAM_IO_IMAGE_HEADER_H_
#define PARKSLAM_IO_IMAGE_HEADER_H_

// The size of an image read from its header, before anything is decoded:
// a 390 KB PNG can declare 20000 x 20000 pixels and take gigabytes to
// decode. PNG, JPEG, BMP and binary PNM (P5, P6) headers are read.

#include <filesystem>
#include <string_view>

#include <opencv2/core.hpp>

namespace parkslam::io {

// Largest image any command decodes: 64 million pixels, 16384 a side
// (a 600 x 600 top view, a 1280 x 960 fisheye and ps2.0's 600 x 600 are
// far below).
inline constexpr long long kMaxImagePixels = 64LL * 1000 * 1000;
inline constexpr int kMaxImageSide = 16384;

// Width and height from the header of an image file's first bytes; throws
// IoError naming `source` when the format is none of those above or the
// header is cut short.
cv::Size ImageSizeFromHeader(std::string_view bytes, std::string_view source);

// Reads the header of `path` and throws IoError naming the file when the
// image is larger than the limits above (or its header cannot be read).
void CheckImageSize(const std::filesystem::path& path);

}  // namespace parkslam::io

#endif  // PARKSLAM_IO_IMAGE_HEADER_H_
