#include "parkslam/io/image_header.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <string>

#include "parkslam/common/plausible_ranges.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/io_error.h"

namespace parkslam::io {
namespace {

std::uint32_t Big16(std::string_view b, size_t at) {
  return (static_cast<unsigned char>(b[at]) << 8) | static_cast<unsigned char>(b[at + 1]);
}
std::uint32_t Big32(std::string_view b, size_t at) {
  return (Big16(b, at) << 16) | Big16(b, at + 2);
}
std::int32_t Little32(std::string_view b, size_t at) {
  std::uint32_t v = 0;
  for (int k = 3; k >= 0; --k)
    v = (v << 8) | static_cast<unsigned char>(b[at + static_cast<size_t>(k)]);
  return static_cast<std::int32_t>(v);
}

[[noreturn]] void Fail(std::string_view source, const std::string& what) {
  ThrowIoError(source, 0, "", what);
}

cv::Size Checked(long long width, long long height, std::string_view source) {
  if (width <= 0 || height <= 0) Fail(source, "the image header declares no pixels");
  return {static_cast<int>(std::min<long long>(width, 1LL << 30)),
          static_cast<int>(std::min<long long>(height, 1LL << 30))};
}

}  // namespace

cv::Size ImageSizeFromHeader(std::string_view b, std::string_view source) {
  // PNG: the signature, then the IHDR chunk: width, height (big-endian).
  if (b.size() >= 8 && b.substr(0, 8) == std::string_view("\x89PNG\r\n\x1a\n", 8)) {
    if (b.size() < 24 || b.substr(12, 4) != "IHDR")
      Fail(source, "a PNG cut short before its header");
    return Checked(Big32(b, 16), Big32(b, 20), source);
  }
  // JPEG: segments up to the first start of frame (SOF0..SOF15 but DHT,
  // JPG and DAC): length, precision, height, width.
  if (b.size() >= 3 && static_cast<unsigned char>(b[0]) == 0xFF &&
      static_cast<unsigned char>(b[1]) == 0xD8) {
    size_t at = 2;
    while (at + 4 <= b.size()) {
      if (static_cast<unsigned char>(b[at]) != 0xFF) Fail(source, "a JPEG whose header is damaged");
      const unsigned marker = static_cast<unsigned char>(b[at + 1]);
      if (marker == 0xFF) {
        ++at;
        continue;
      }
      const std::uint32_t length = Big16(b, at + 2);
      if (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC) {
        if (at + 9 > b.size()) break;
        return Checked(Big16(b, at + 7), Big16(b, at + 5), source);
      }
      if (length < 2) Fail(source, "a JPEG whose header is damaged");
      at += 2 + length;
    }
    Fail(source, "a JPEG cut short before its frame header");
  }
  // BMP: width and height (negative: top-down) at 18 and 22, little-endian.
  if (b.size() >= 2 && b[0] == 'B' && b[1] == 'M') {
    if (b.size() < 26) Fail(source, "a BMP cut short before its header");
    const long long h = Little32(b, 22);
    return Checked(Little32(b, 18), h < 0 ? -h : h, source);
  }
  // Binary PNM: "P5" or "P6", then width and height as text (comments '#').
  if (b.size() >= 2 && b[0] == 'P' && (b[1] == '5' || b[1] == '6')) {
    long long values[2] = {0, 0};
    size_t at = 2;
    for (long long& v : values) {
      while (at < b.size() && (std::isspace(static_cast<unsigned char>(b[at])) || b[at] == '#')) {
        if (b[at] == '#') {
          while (at < b.size() && b[at] != '\n') ++at;
        } else {
          ++at;
        }
      }
      if (at >= b.size() || !std::isdigit(static_cast<unsigned char>(b[at])))
        Fail(source, "a PNM whose header is damaged");
      while (at < b.size() && std::isdigit(static_cast<unsigned char>(b[at])) && v < (1LL << 40)) {
        v = v * 10 + (b[at++] - '0');
      }
    }
    return Checked(values[0], values[1], source);
  }
  Fail(source, "not a PNG, JPEG, BMP or binary PNM image");
}

void CheckImageSize(const std::filesystem::path& path) {
  CheckInputFile(path, kMaxImageBytes);  // no FIFO, device or huge file
  std::ifstream in(path, std::ios::binary);
  if (!in) ThrowIoError(path.string(), 0, "", "cannot open");
  // JPEG headers (EXIF, thumbnails) can run long before the frame header.
  std::string bytes(256 * 1024, '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  bytes.resize(static_cast<size_t>(in.gcount()));
  const cv::Size size = ImageSizeFromHeader(bytes, path.string());
  if (size.width > kMaxImageSide_px || size.height > kMaxImageSide_px ||
      static_cast<long long>(size.width) * size.height > kMaxImagePixels) {
    ThrowIoError(path.string(), 0, "",
                 "an image of " + std::to_string(size.width) + " x " + std::to_string(size.height) +
                     " pixels; at most " + std::to_string(kMaxImageSide_px) + " a side and " +
                     std::to_string(kMaxImagePixels) + " pixels are read");
  }
  // A cut file decodes with a grey lower part and a library warning only.
  CheckImageEnds(path);
}

void CheckImageEnds(const std::filesystem::path& path) {
  CheckInputFile(path, kMaxImageBytes);
  std::ifstream in(path, std::ios::binary);
  if (!in) ThrowIoError(path.string(), 0, "", "cannot open");
  std::string head(8, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  const bool png = head == std::string_view("\x89PNG\r\n\x1a\n", 8);
  const bool jpeg = head.size() >= 2 && static_cast<unsigned char>(head[0]) == 0xFF &&
                    static_cast<unsigned char>(head[1]) == 0xD8;
  if (!png && !jpeg) return;
  in.clear();
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  constexpr std::streamoff kTail = 4096;
  in.seekg(std::max<std::streamoff>(0, size - kTail));
  std::string tail(static_cast<size_t>(std::min(size, kTail)), '\0');
  in.read(tail.data(), static_cast<std::streamsize>(tail.size()));
  tail.resize(static_cast<size_t>(in.gcount()));
  if (png && tail.find("IEND") == std::string::npos) {
    ThrowIoError(path.string(), 0, "",
                 "a PNG cut short (" + std::to_string(size) + " bytes, no IEND chunk at its end)");
  }
  // The marker after the header: a 2-byte file's FF D8 is no end.
  if (jpeg && (size < 4 || tail.rfind("\xFF\xD9") == std::string::npos ||
               (size <= kTail && tail.rfind("\xFF\xD9") < 2))) {
    ThrowIoError(path.string(), 0, "",
                 "a JPEG cut short (" + std::to_string(size) +
                     " bytes, no end-of-image marker FF D9 at its end)");
  }
}

}  // namespace parkslam::io
