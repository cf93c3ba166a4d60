#ifndef PARKSLAM_SCENE_FONT_BOOK_H_
#define PARKSLAM_SCENE_FONT_BOOK_H_

// Real fonts for painted slot IDs and floor text: the sans-serif,
// condensed and monospaced faces of Debian's font packages (DejaVu,
// Liberation, FreeFont, URW's Nimbus, Noto, Open Sans, Roboto, Cantarell),
// drawn by FreeType through OpenCV's freetype module, and OpenCV's own
// stroke (Hershey) fonts, which are always there; and the default lot's
// seven-segment face, so that a reader trained on these scenes also reads
// the simulator's own IDs.
//
// Not thread-safe: each thread keeps its own book.

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace cv::freetype {
class FreeType2;
}

namespace parkslam::scene {

// The usable font files below `root` (by default the system's font
// folder), sorted by path so that a font index means the same face on
// machines with the same packages.
std::vector<std::filesystem::path> FindFloorFonts(
    const std::filesystem::path& root = "/usr/share/fonts");

class FontBook {
 public:
  explicit FontBook(std::vector<std::filesystem::path> files);
  ~FontBook();
  FontBook(const FontBook&) = delete;
  FontBook& operator=(const FontBook&) = delete;

  // The number of faces: the files, then the stroke fonts.
  int size() const;
  int file_count() const { return static_cast<int>(files_.size()); }
  const std::vector<std::filesystem::path>& files() const { return files_; }

  // `text` drawn white on black (CV_8UC1), its digits' and capitals' height
  // cap_height_px, upright, with a margin of a quarter of that height all
  // round. `font` is taken modulo size().
  cv::Mat Draw(const std::string& text, int font, double cap_height_px);

  // The same in the default lot's seven-segment face (font/digit_font.h),
  // digit height cap_height_px: the IDs the simulator paints. Characters
  // other than digits leave a blank digit cell.
  static cv::Mat DrawSevenSegment(const std::string& text, double cap_height_px);

 private:
  std::vector<std::filesystem::path> files_;
  std::map<int, cv::Ptr<cv::freetype::FreeType2>> loaded_;
};

}  // namespace parkslam::scene

#endif  // PARKSLAM_SCENE_FONT_BOOK_H_
