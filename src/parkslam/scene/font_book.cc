#include "parkslam/scene/font_book.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <opencv2/freetype.hpp>
#include <opencv2/imgproc.hpp>
#include <system_error>

#include "parkslam/font/digit_font.h"

namespace parkslam::scene {
namespace {

// Faces that look like floor paint: plain sans-serif, condensed and mono
// families (and one bold serif), by file-name prefix.
constexpr std::array<const char*, 20> kFamilies = {
    "DejaVuSans", "LiberationSans",       "LiberationMono",   "FreeSans",
    "FreeMono",   "NimbusSans",           "NimbusMonoPS",     "URWGothic",
    "NotoSans-",  "NotoSansMono-",        "NotoSansDisplay-", "OpenSans",
    "Roboto-",    "RobotoCondensed-",     "Cantarell",        "DroidSansMono",
    "NotoMono",   "LiberationSansNarrow", "RobotoMono-",      "FreeSerifBold"};

constexpr std::array<int, 4> kStrokeFonts = {cv::FONT_HERSHEY_SIMPLEX, cv::FONT_HERSHEY_DUPLEX,
                                             cv::FONT_HERSHEY_COMPLEX, cv::FONT_HERSHEY_TRIPLEX};

bool Usable(const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  if (ext != ".ttf" && ext != ".otf") return false;
  const std::string name = path.filename().string();
  std::string lower = name;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const char* bad : {"italic", "oblique", "math", "fallback", "light", "thin", "symbol"}) {
    if (lower.find(bad) != std::string::npos) return false;
  }
  return std::any_of(kFamilies.begin(), kFamilies.end(),
                     [&](const char* family) { return name.rfind(family, 0) == 0; });
}

}  // namespace

std::vector<std::filesystem::path> FindFloorFonts(const std::filesystem::path& root) {
  std::vector<std::filesystem::path> files;
  std::error_code ec;
  if (!std::filesystem::is_directory(root, ec)) return files;
  for (auto it = std::filesystem::recursive_directory_iterator(
           root, std::filesystem::directory_options::skip_permission_denied, ec);
       !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
    if (it->is_regular_file(ec) && Usable(it->path())) files.push_back(it->path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

FontBook::FontBook(std::vector<std::filesystem::path> files) : files_(std::move(files)) {}
FontBook::~FontBook() = default;

int FontBook::size() const { return static_cast<int>(files_.size() + kStrokeFonts.size()); }

cv::Mat FontBook::Draw(const std::string& text, int font, double cap_height_px) {
  const int index = ((font % size()) + size()) % size();
  const int cap = std::max(4, static_cast<int>(std::lround(cap_height_px)));
  const int margin = std::max(2, cap / 4);
  if (index < file_count()) {
    auto it = loaded_.find(index);
    if (it == loaded_.end()) {
      cv::Ptr<cv::freetype::FreeType2> face = cv::freetype::createFreeType2();
      face->loadFontData(files_[static_cast<size_t>(index)].string(), 0);
      it = loaded_.emplace(index, face).first;
    }
    // FreeType's height is the em; capitals and digits are about 0.72 of it.
    const int em = std::max(6, static_cast<int>(std::lround(cap / 0.72)));
    int baseline = 0;
    const cv::Size size = it->second->getTextSize(text, em, -1, &baseline);
    // FreeType draws into colour images only.
    cv::Mat canvas(std::max(1, cap + 2 * margin), std::max(1, size.width + 2 * margin), CV_8UC3,
                   cv::Scalar::all(0));
    it->second->putText(canvas, text, cv::Point(margin, margin + cap), em, cv::Scalar::all(255), -1,
                        cv::LINE_AA, true);
    cv::Mat mask;
    cv::extractChannel(canvas, mask, 0);
    return mask;
  }
  const int face = kStrokeFonts[static_cast<size_t>(index - file_count())];
  const int thickness = std::max(1, cap / 7);
  const double scale = cv::getFontScaleFromHeight(face, cap, thickness);
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text, face, scale, thickness, &baseline);
  cv::Mat mask(cap + 2 * margin, size.width + 2 * margin, CV_8UC1, cv::Scalar(0));
  cv::putText(mask, text, cv::Point(margin, margin + cap), face, scale, cv::Scalar(255), thickness,
              cv::LINE_AA);
  return mask;
}

cv::Mat FontBook::DrawSevenSegment(const std::string& text, double cap_height_px) {
  const double h = std::max(4.0, cap_height_px);
  const int margin = std::max(2, static_cast<int>(std::lround(h / 4)));
  const int n = std::max(1, static_cast<int>(text.size()));
  const double width = font::IdWidth(n, h);
  cv::Mat mask(static_cast<int>(std::ceil(h)) + 2 * margin,
               static_cast<int>(std::ceil(width)) + 2 * margin, CV_8UC1, cv::Scalar(0));
  const double stroke = font::kDigitStroke * h;
  const double advance = (font::kDigitWidth + font::kDigitGap) * h;
  for (size_t k = 0; k < text.size(); ++k) {
    // Glyph y is up from the digit's foot; image rows go down.
    const double left = margin + advance * static_cast<double>(k);
    const double foot = margin + h;
    font::DrawSevenSegmentDigit(
        text[k], h, stroke,
        [&](double x, double y) -> Eigen::Vector2d {
          return {left + x, foot - y};
        },
        255, &mask);
  }
  return mask;
}

}  // namespace parkslam::scene
