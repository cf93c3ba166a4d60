#ifndef PARKSLAM_IO_IMAGE_HEADER_H_
#define PARKSLAM_IO_IMAGE_HEADER_H_

// The size of an image read from its header, before anything is decoded:
// a 390 KB PNG can declare 20000 x 20000 pixels and take gigabytes to
// decode. PNG, JPEG, BMP and binary PNM (P5, P6) headers are read.

#include <filesystem>
#include <string_view>

#include <opencv2/core.hpp>

namespace parkslam::io {

// Width and height from the header of an image file's first bytes; throws
// IoError naming `source` when the format is none of those above or the
// header is cut short.
cv::Size ImageSizeFromHeader(std::string_view bytes, std::string_view source);

// Reads the header of `path` and throws IoError naming the file when the
// image is larger than the largest any command decodes, kMaxImageSide_px a
// side and kMaxImagePixels (common/plausible_ranges.h), its header cannot
// be read, or it is cut short (CheckImageEnds).
void CheckImageSize(const std::filesystem::path& path);

// Throws IoError naming the file when a JPEG or PNG is cut short: a JPEG
// ends with its end-of-image marker (FF D9), a PNG with its IEND chunk,
// and a cut file has neither in its last bytes (some cameras append a few
// bytes after the marker, so the last 4 KB are searched). Reads only the
// file's head and tail; other formats pass.
void CheckImageEnds(const std::filesystem::path& path);

}  // namespace parkslam::io

#endif  // PARKSLAM_IO_IMAGE_HEADER_H_
