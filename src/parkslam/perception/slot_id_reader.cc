#include "parkslam/perception/slot_id_reader.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <stdexcept>
#include <vector>

#include "parkslam/common/field_checker.h"
#include "parkslam/font/digit_font.h"

namespace parkslam::perception {
namespace {

// The rectified region reaches this far beyond where the digits may lie.
constexpr double kRegionMarginM = 0.1;
// Paint is there when its contrast over the floor is at least this many
// grey levels and this many times the floor's noise.
constexpr double kMinContrastGrey = 15.0;
constexpr double kMinContrastNoise = 4.0;
// Percentiles of the region's grey levels: the floor, the floor's noise
// (as a Gaussian's 30th and 10th percentiles lie 0.757 sigma apart), and the
// paint (IDs cover 6 % ("11") to 30 % ("888") of the region).
constexpr double kFloorPercentile = 0.3;
constexpr double kNoisePercentile = 0.1;
constexpr double kNoisePercentileSpread = 0.757;
constexpr double kPaintPercentile = 0.975;
// Soft ink map: normalized value (0 floor, 1 paint) to ink share. High, so
// that it keeps the strokes' cores and not the halo that blur spreads
// around them: a layout would move to take in the halo beside a "1".
constexpr float kInkLow = 0.45f, kInkHigh = 0.85f;
// A digit cell holds at least this share of one full-height stroke of ink
// ("1" holds exactly one).
constexpr double kMinCellInkStrokes = 0.4;
// Layout score lost per pixel of offset from the nominal place, in ink
// pixels: it only decides between layouts that explain the ink equally
// ("1" leaves its cell's left part empty).
constexpr double kOffsetPenaltyPerPx = 1.0;
constexpr double kLayoutStepPx = 0.5;
// A layout may leave at most this share of the band's ink (against the ink
// in its cells) outside its cells: read IDs leave 6 % (median), up to 45 %
// with the entrance 8 cm off.
constexpr double kMaxStrayInk = 0.5;
// A digit cell may hold at most this share of pixels no camera saw.
constexpr double kMaxNoDataShare = 0.02;
// The reference lines are sampled at these depths (as the digits) and
// across them within this distance of the corner.
constexpr std::array<double, 7> kLineDepthsM = {0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9};
constexpr double kLineSearchM = 0.3;
constexpr int kMinLineSamples = 3;

struct Histogram {
  std::array<int, 256> counts{};
  int total = 0;

  // The smallest level with at least `share` of the samples at or below it.
  int Percentile(double share) const {
    const double target = share * total;
    int cumulative = 0;
    for (int v = 0; v < 256; ++v) {
      cumulative += counts[static_cast<size_t>(v)];
      if (cumulative >= target && cumulative > 0) return v;
    }
    return 255;
  }
};

// Sums of a profile over continuous intervals. Pixel coordinates here and
// below are continuous, pixel i covering [i - 0.5, i + 0.5) with its value
// spread evenly.
class ProfileSums {
 public:
  explicit ProfileSums(const std::vector<double>& profile) : cumulative_(profile.size() + 1, 0.0) {
    for (size_t i = 0; i < profile.size(); ++i) cumulative_[i + 1] = cumulative_[i] + profile[i];
  }
  // Sum over [a, b).
  double Sum(double a, double b) const { return Below(b) - Below(a); }

 private:
  double Below(double x) const {
    const size_t n = cumulative_.size() - 1;
    const double edge = std::clamp(x + 0.5, 0.0, static_cast<double>(n));
    const auto whole = static_cast<size_t>(edge);
    if (whole >= n) return cumulative_[n];
    const double part = edge - static_cast<double>(whole);
    return cumulative_[whole] + part * (cumulative_[whole + 1] - cumulative_[whole]);
  }

  std::vector<double> cumulative_;
};

// Bilinear grey level at a top-view point; nullopt outside the image or
// next to a pixel no camera saw (0).
std::optional<double> SampleGrey(const cv::Mat& image, const Eigen::Vector2d& p) {
  const double x = std::floor(p.x()), y = std::floor(p.y());
  if (!(x >= 0.0 && y >= 0.0 && x + 1 < image.cols && y + 1 < image.rows)) return std::nullopt;
  const int c = static_cast<int>(x), r = static_cast<int>(y);
  const double fx = p.x() - x, fy = p.y() - y;
  const double v00 = image.at<std::uint8_t>(r, c), v01 = image.at<std::uint8_t>(r, c + 1);
  const double v10 = image.at<std::uint8_t>(r + 1, c), v11 = image.at<std::uint8_t>(r + 1, c + 1);
  if (v00 == 0 || v01 == 0 || v10 == 0 || v11 == 0) return std::nullopt;
  return (1 - fy) * ((1 - fx) * v00 + fx * v01) + fy * ((1 - fx) * v10 + fx * v11);
}

// The paint level of the separating line through `corner_px`, running
// along `up`: the brightest point across it, at the digits' depths; the
// median over depths. nullopt when too little of it is seen.
std::optional<double> LinePaintGrey(const cv::Mat& image, const Eigen::Vector2d& corner_px,
                                    const Eigen::Vector2d& up, const Eigen::Vector2d& right,
                                    double pixels_per_m) {
  std::vector<double> peaks;
  const int half = static_cast<int>(std::ceil(kLineSearchM * pixels_per_m));
  for (double depth_m : kLineDepthsM) {
    const Eigen::Vector2d on_line = corner_px + up * (depth_m * pixels_per_m);
    double peak = -1.0;
    for (int t = -half; t <= half; ++t) {
      const std::optional<double> v = SampleGrey(image, on_line + right * t);
      if (!v) {
        peak = -1.0;
        break;
      }
      peak = std::max(peak, *v);
    }
    if (peak >= 0.0) peaks.push_back(peak);
  }
  if (static_cast<int>(peaks.size()) < kMinLineSamples) return std::nullopt;
  std::nth_element(peaks.begin(), peaks.begin() + static_cast<long>(peaks.size() / 2), peaks.end());
  return peaks[peaks.size() / 2];
}

struct Layout {
  int digits = 0;
  double left_px = 0.0;    // left edge of the first digit, in region columns
  double stray_ink = 0.0;  // band ink outside its cells, as a share of the ink inside
  double score = -1e300;
};

// The region where the digits may stand, rectified (paper III-A): upright,
// one pixel per top-view pixel. Columns run along the reading direction
// `right` (up turned clockwise on screen), rows from the digits' top down
// to their foot.
struct Region {
  double ppm = 0.0;
  Eigen::Vector2d up, right;
  double height_px = 0.0, width_px = 0.0, pitch_px = 0.0, stroke_px = 0.0;
  double shift_px = 0.0;      // how far the digits may lie off their place
  double max_width_px = 0.0;  // the longest ID's width
  int cols = 0, rows = 0;
  double center_col = 0.0;
  double nominal_top = 0.0;  // the digits' top edge, in rows
  cv::Mat grey;
  // Pixels no camera saw (0 in the top view, or outside it), grown by one
  // for the interpolation's reach.
  cv::Mat no_data;
};

Region Rectify(const cv::Mat& top_view_grey, const EntranceInImage& entrance,
               const SlotIdReaderOptions& options) {
  Region g;
  g.ppm = options.pixels_per_m;
  g.up = entrance.depth_dir_px / entrance.depth_dir_px.norm();
  g.right = Eigen::Vector2d(-g.up.y(), g.up.x());
  const Eigen::Vector2d mid = (entrance.corner0_px + entrance.corner1_px) / 2;
  g.height_px = options.id_height_m * g.ppm;
  g.width_px = font::kDigitWidth * g.height_px;
  g.pitch_px = (font::kDigitWidth + font::kDigitGap) * g.height_px;
  g.stroke_px = font::kDigitStroke * g.height_px;
  g.shift_px = options.max_offset_m * g.ppm;
  const double margin_px = kRegionMarginM * g.ppm;
  g.max_width_px = font::IdWidth(options.max_digits, g.height_px);
  g.cols = static_cast<int>(std::ceil(g.max_width_px + 2 * (g.shift_px + margin_px))) + 1;
  g.rows = static_cast<int>(std::ceil(g.height_px + 2 * (g.shift_px + margin_px))) + 1;
  g.center_col = (g.cols - 1) / 2.0;
  // Row r lies (top_depth_px - r) pixels deep into the slot.
  const double top_depth_px =
      (options.id_setback_m + options.id_height_m) * g.ppm + g.shift_px + margin_px;
  g.nominal_top = g.shift_px + margin_px;
  const Eigen::Vector2d origin = mid - g.right * g.center_col + g.up * top_depth_px;
  const cv::Matx23d region_to_image(g.right.x(), -g.up.x(), origin.x(), g.right.y(), -g.up.y(),
                                    origin.y());
  cv::Mat seen;
  cv::warpAffine(top_view_grey, g.grey, region_to_image, cv::Size(g.cols, g.rows),
                 cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::warpAffine(top_view_grey, seen, region_to_image, cv::Size(g.cols, g.rows),
                 cv::INTER_NEAREST | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT, cv::Scalar(0));
  g.no_data = seen == 0;
  cv::dilate(g.no_data, g.no_data, cv::Mat());
  return g;
}

// The region's grey levels where a camera saw it.
Histogram LevelsOf(const Region& g) {
  Histogram levels;
  for (int r = 0; r < g.rows; ++r) {
    const std::uint8_t* v = g.grey.ptr<std::uint8_t>(r);
    const std::uint8_t* n = g.no_data.ptr<std::uint8_t>(r);
    for (int c = 0; c < g.cols; ++c) {
      if (n[c]) continue;
      ++levels.counts[v[c]];
      ++levels.total;
    }
  }
  return levels;
}

// The columns any ID may cover, [begin, end).
std::pair<int, int> IdWindow(const Region& g) {
  return {
      std::max(0, static_cast<int>(std::floor(g.center_col - g.max_width_px / 2 - g.shift_px))),
      std::min(g.cols,
               static_cast<int>(std::ceil(g.center_col + g.max_width_px / 2 + g.shift_px)) + 1)};
}

// The digits' band (all digits span the full height): its top row, where
// the ink over the window's columns is largest, less the offset penalty.
double FindBandTop(const Region& g, const cv::Mat& ink) {
  const auto [window_begin, window_end] = IdWindow(g);
  std::vector<double> row_ink(static_cast<size_t>(g.rows), 0.0);
  for (int r = 0; r < g.rows; ++r) {
    const float* k = ink.ptr<float>(r);
    for (int c = window_begin; c < window_end; ++c) row_ink[static_cast<size_t>(r)] += k[c];
  }
  const ProfileSums row_sums(row_ink);
  double top = g.nominal_top, best_band = -1e300;
  for (double t = g.nominal_top - g.shift_px; t <= g.nominal_top + g.shift_px + 1e-9;
       t += kLayoutStepPx) {
    const double score =
        row_sums.Sum(t, t + g.height_px) - kOffsetPenaltyPerPx * std::abs(t - g.nominal_top);
    if (score > best_band) {
      best_band = score;
      top = t;
    }
  }
  return top;
}

// Column profiles over the band, and over its top and bottom thirds: every
// digit of the font has ink in both (segments a, b or f above, c, d or e
// below), other paint reaching into a cell (an angled slot's entrance stub)
// mostly not; and the pixels no camera saw.
struct ColumnProfiles {
  ProfileSums ink, top, bottom, unseen;
};

ColumnProfiles ProfilesOf(const Region& g, const cv::Mat& ink, double band_top) {
  const double band_bottom = band_top + g.height_px;
  const auto cols = static_cast<size_t>(g.cols);
  std::vector<double> col_ink(cols, 0.0), col_ink_top(cols, 0.0), col_ink_bottom(cols, 0.0),
      col_unseen(cols, 0.0);
  for (int r = std::max(0, static_cast<int>(std::ceil(band_top)));
       r < std::min(g.rows, static_cast<int>(std::ceil(band_bottom))); ++r) {
    const float* k = ink.ptr<float>(r);
    const std::uint8_t* n = g.no_data.ptr<std::uint8_t>(r);
    const bool in_top = r < band_top + g.height_px / 3;
    const bool in_bottom = r >= band_bottom - g.height_px / 3;
    for (int c = 0; c < g.cols; ++c) {
      col_ink[static_cast<size_t>(c)] += k[c];
      if (in_top) col_ink_top[static_cast<size_t>(c)] += k[c];
      if (in_bottom) col_ink_bottom[static_cast<size_t>(c)] += k[c];
      col_unseen[static_cast<size_t>(c)] += n[c] ? 1.0 : 0.0;
    }
  }
  return {ProfileSums(col_ink), ProfileSums(col_ink_top), ProfileSums(col_ink_bottom),
          ProfileSums(col_unseen)};
}

struct LayoutSearch {
  Layout best;
  // Per digit count, the best score of a layout left open (not explaining
  // the ink, a cell partly unseen).
  std::vector<double> best_open_score;
  double min_cell_ink = 0.0;
};

// Every candidate layout: n digits centred `shift` off the nominal place.
// It explains the ink when each of its cells holds a digit's worth, top and
// bottom; it is ruled out when one of its cells, fully seen, does not; else
// it stays open (a cell without ink lies partly where no camera saw). Its
// score: the ink inside its cells less the ink outside, plus the ink in
// each cell's right stroke (segments b and c): every digit of the font has
// one of them, and it pins a "1", which would otherwise slide freely in its
// cell.
LayoutSearch FindLayout(const Region& g, const ColumnProfiles& p, int max_digits) {
  const auto [window_begin, window_end] = IdWindow(g);
  const double window_ink = p.ink.Sum(window_begin - 0.5, window_end - 0.5);
  LayoutSearch search;
  search.min_cell_ink = kMinCellInkStrokes * g.stroke_px * g.height_px;
  const double min_third_ink = search.min_cell_ink / 3;
  const double max_cell_unseen = kMaxNoDataShare * g.width_px * g.height_px;
  search.best_open_score.assign(static_cast<size_t>(max_digits) + 1, -1e300);
  for (int n = 1; n <= max_digits; ++n) {
    const double id_width_px = font::IdWidth(n, g.height_px);
    for (double shift = -g.shift_px; shift <= g.shift_px + 1e-9; shift += kLayoutStepPx) {
      const double left = g.center_col + shift - id_width_px / 2;
      double inside = 0.0, right_strokes = 0.0;
      bool explains = true, ruled_out = false;
      for (int k = 0; k < n; ++k) {
        const double a = left + k * g.pitch_px, b = a + g.width_px;
        const double cell = p.ink.Sum(a, b);
        if (cell < search.min_cell_ink || p.top.Sum(a, b) < min_third_ink ||
            p.bottom.Sum(a, b) < min_third_ink) {
          explains = false;
          ruled_out = ruled_out || p.unseen.Sum(a, b) <= max_cell_unseen;
        }
        inside += cell;
        right_strokes += p.ink.Sum(b - g.stroke_px, b);
      }
      const double score =
          inside - (window_ink - inside) + right_strokes - kOffsetPenaltyPerPx * std::abs(shift);
      if (!explains) {
        double& open = search.best_open_score[static_cast<size_t>(n)];
        if (!ruled_out) open = std::max(open, score);
        continue;
      }
      if (score > search.best.score) {
        search.best = {n, left, (window_ink - inside) / inside, score};
      }
    }
  }
  return search;
}

// Why the best layout cannot be trusted, or null: a longer ID, partly out
// of sight, that explains the ink seen about as well (a digit cut off would
// be read as another, or the ID as a shorter one); or digits not seen with
// the classifier's margins.
const char* LayoutDoubt(const Region& g, const LayoutSearch& search, const ColumnProfiles& p,
                        int max_digits) {
  const Layout& layout = search.best;
  for (int n = layout.digits + 1; n <= max_digits; ++n) {
    if (search.best_open_score[static_cast<size_t>(n)] >= layout.score - search.min_cell_ink) {
      return "maybe longer";
    }
  }
  const double pad = kDigitPatchMarginX * g.height_px;
  const double id_width_px = font::IdWidth(layout.digits, g.height_px);
  const double unseen = p.unseen.Sum(layout.left_px - pad, layout.left_px + id_width_px + pad);
  if (unseen > kMaxNoDataShare * (id_width_px + 2 * pad) * g.height_px) return "not seen";
  return nullptr;
}

// Each digit cell, rectified to the classifier's patch (drawn at twice its
// resolution and averaged down, as the classifier was trained), and
// classified; digits below min_digit_probability stay unread.
SlotIdReading ReadDigits(const Region& g, const cv::Mat& normalized, const Layout& layout,
                         double band_top, const DigitClassifier& classifier,
                         const SlotIdReaderOptions& options, SlotIdReadDetails* details) {
  SlotIdReading reading;
  const cv::Size big(2 * kDigitPatchCols, 2 * kDigitPatchRows);
  for (int k = 0; k < layout.digits; ++k) {
    const double cell_left = layout.left_px + k * g.pitch_px - kDigitPatchMarginX * g.height_px;
    const double cell_top = band_top - kDigitPatchMarginY * g.height_px;
    const double step_x = (g.width_px + 2 * kDigitPatchMarginX * g.height_px) / big.width;
    const double step_y = (g.height_px + 2 * kDigitPatchMarginY * g.height_px) / big.height;
    // Patch pixel i samples the region at cell_left + (i + 0.5) step_x.
    const cv::Matx23d patch_to_region(step_x, 0, cell_left + 0.5 * step_x, 0, step_y,
                                      cell_top + 0.5 * step_y);
    cv::Mat fine, patch;
    cv::warpAffine(normalized, fine, patch_to_region, big, cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                   cv::BORDER_REPLICATE);
    cv::resize(fine, patch, cv::Size(kDigitPatchCols, kDigitPatchRows), 0, 0, cv::INTER_AREA);
    const ClassProbabilities p = classifier.Classify(patch);
    if (details != nullptr) details->digit_patches.push_back(patch);
    DigitReading digit;
    double best = 0.0;
    for (int c = 0; c < 10; ++c) best = std::max(best, p[static_cast<size_t>(c)]);
    if (best >= options.min_digit_probability) {
      for (int c = 0; c < 10; ++c) {
        if (p[static_cast<size_t>(c)] >= options.min_hypothesis_probability) {
          digit.hypotheses.push_back({static_cast<char>('0' + c), p[static_cast<size_t>(c)]});
        }
      }
      std::sort(digit.hypotheses.begin(), digit.hypotheses.end(),
                [](const DigitHypothesis& a, const DigitHypothesis& b) {
                  return a.probability > b.probability;
                });
    }
    reading.digits.push_back(std::move(digit));
  }
  return reading;
}

}  // namespace

bool SlotIdReaderOptions::IsValid(std::string* error) const {
  FieldChecker c(error);
  c.PositiveAtMost(pixels_per_m, 1000.0, "pixels_per_m", "px/m");
  c.PositiveAtMost(id_height_m, 3.0, "id_height_m", "m");
  c.Require(id_height_m * pixels_per_m >= 12.0, "id_height_m",
            "must come to at least 12 px at pixels_per_m: smaller digits are not read");
  c.InRange(id_setback_m, 0.0, 5.0, "id_setback_m", "m");
  c.InRange(max_digits, 1, 6, "max_digits", "");
  c.PositiveAtMost(min_hypothesis_probability, 1.0, "min_hypothesis_probability", "");
  c.InRange(min_digit_probability, min_hypothesis_probability, 1.0, "min_digit_probability", "");
  c.InRange(max_offset_m, 0.0, 1.0, "max_offset_m", "m");
  c.Rate(min_paint_ratio, "min_paint_ratio");
  return c.ok();
}

SlotIdReader::SlotIdReader(const SlotIdReaderOptions& options) : options_(options) {
  std::string error;
  if (!options_.IsValid(&error)) throw std::invalid_argument("SlotIdReaderOptions: " + error);
  classifier_ = &DigitClassifier::Default();
}

SlotIdReading SlotIdReader::Read(const cv::Mat& top_view_grey,
                                 const EntranceInImage& entrance) const {
  return Read(top_view_grey, entrance, nullptr);
}

SlotIdReading SlotIdReader::Read(const cv::Mat& top_view_grey, const EntranceInImage& entrance,
                                 SlotIdReadDetails* details) const {
  if (top_view_grey.type() != CV_8UC1)
    throw std::invalid_argument("SlotIdReader: expected an 8-bit grey image");
  SlotIdReadDetails local;
  SlotIdReadDetails& d = details != nullptr ? *details : local;
  d = SlotIdReadDetails{};
  const auto give_up = [&d](const char* why) {
    d.outcome = why;
    return SlotIdReading{};
  };
  const double norm = entrance.depth_dir_px.norm();
  if (!(norm > 1e-9) || !entrance.corner0_px.allFinite() || !entrance.corner1_px.allFinite()) {
    return give_up("bad entrance");
  }
  const Region g = Rectify(top_view_grey, entrance, options_);

  // Floor and paint levels from the region's histogram. Blurred far from
  // the car, a three-digit ID and its halo cover up to 40 % of the region:
  // the floor's median is about the 30th percentile, its spread shows below
  // it, and the 97.5th percentile is paint.
  const Histogram levels = LevelsOf(g);
  if (levels.total < g.rows * g.cols / 2) return give_up("region not seen");
  const int floor_grey = levels.Percentile(kFloorPercentile);
  const double noise_grey =
      std::max(1.0, (floor_grey - levels.Percentile(kNoisePercentile)) / kNoisePercentileSpread);
  const double contrast_grey = levels.Percentile(kPaintPercentile) - floor_grey;
  d.contrast_grey = contrast_grey;
  d.noise_grey = noise_grey;
  if (contrast_grey < std::max(kMinContrastGrey, kMinContrastNoise * noise_grey)) {
    return give_up("no paint");
  }

  // Normalized (floor 0, paint 1) and soft ink maps.
  cv::Mat normalized;
  g.grey.convertTo(normalized, CV_32F, 1.0 / contrast_grey, -floor_grey / contrast_grey);
  normalized.setTo(0.0f, g.no_data);
  cv::Mat ink = (normalized - kInkLow) * (1.0f / (kInkHigh - kInkLow));
  cv::min(cv::max(ink, 0.0f), 1.0f, ink);

  // Layout: the digits' band, then how many digits and where along it.
  const double band_top = FindBandTop(g, ink);
  const ColumnProfiles profiles = ProfilesOf(g, ink, band_top);
  const LayoutSearch search = FindLayout(g, profiles, options_.max_digits);
  const Layout& layout = search.best;
  if (layout.digits == 0) return give_up("no digits");
  d.digits_found = layout.digits;
  d.stray_ink = layout.stray_ink;
  d.offset_px = {layout.left_px + font::IdWidth(layout.digits, g.height_px) / 2 - g.center_col,
                 g.nominal_top - band_top};
  // Paint the layout leaves out: digits beyond the search range (the
  // entrance far off), or other paint.
  if (layout.stray_ink > kMaxStrayInk) return give_up("stray paint");
  if (const char* why = LayoutDoubt(g, search, profiles, options_.max_digits)) return give_up(why);

  // Worn paint: fainter than the slot's own lines.
  const std::optional<double> line0 =
      LinePaintGrey(top_view_grey, entrance.corner0_px, g.up, g.right, g.ppm);
  const std::optional<double> line1 =
      LinePaintGrey(top_view_grey, entrance.corner1_px, g.up, g.right, g.ppm);
  if (line0 || line1) {
    const double line_grey = std::max(line0.value_or(0.0), line1.value_or(0.0));
    d.paint_ratio = contrast_grey / std::max(line_grey - floor_grey, 1.0);
    if (d.paint_ratio < options_.min_paint_ratio) return give_up("worn");
  }

  const SlotIdReading reading =
      ReadDigits(g, normalized, layout, band_top, *classifier_, options_, details);
  const bool any_read = std::any_of(reading.digits.begin(), reading.digits.end(),
                                    [](const DigitReading& digit) { return digit.read(); });
  if (!any_read) return give_up("unread");
  d.outcome = reading.partial() ? "partial" : "read";
  return reading;
}

}  // namespace parkslam::perception
