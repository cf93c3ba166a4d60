#include "parkslam/perception/slot_detector.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "parkslam/common/angles.h"
#include "parkslam/common/cross.h"
#include "parkslam/common/field_checker.h"

namespace parkslam::perception {
namespace {

// z-component of the cross product of two image vectors.
// A painted line: its centreline through `point` along unit `dir`, painted
// from point + t0 dir to point + t1 dir (t0 < t1), width_px wide.
struct PaintLine {
  Eigen::Vector2d point = Eigen::Vector2d::Zero();
  Eigen::Vector2d dir = Eigen::Vector2d::UnitX();
  double t0 = 0.0, t1 = 0.0;
  double width_px = 0.0;
  double contrast = 0.0;  // median brightness above the floor on the centreline
  // Share of the centreline brighter than the floor on both sides.
  double two_sided_share = 1.0;

  double Along(const Eigen::Vector2d& p) const { return (p - point).dot(dir); }
  double Across(const Eigen::Vector2d& p) const { return Cross(dir, p - point); }
  double length() const { return t1 - t0; }
};

// Bilinear sample of a CV_8UC1 image; 0 outside.
double Sample(const cv::Mat& image, double x, double y) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= image.cols || y0 + 1 >= image.rows) return 0.0;
  const double fx = x - x0, fy = y - y0;
  const std::uint8_t* r0 = image.ptr<std::uint8_t>(y0);
  const std::uint8_t* r1 = image.ptr<std::uint8_t>(y0 + 1);
  return (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) +
         fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
}

// The brightness of structures narrower than about half of kernel_px above
// the floor around them: the grey image less its median over kernel_px
// (negative values clipped). A median, unlike a morphological opening, is
// not dragged down by dark specks, cracks or tile joints beside a line.
// The median is taken at reduced resolution (a painted line stays well
// under half its window) and interpolated back.
cv::Mat BrightAboveFloor(const cv::Mat& grey, int kernel_px) {
  const int shrink = std::max(1, kernel_px / 9);
  cv::Mat small, small_floor, floor;
  cv::resize(grey, small, cv::Size(), 1.0 / shrink, 1.0 / shrink, cv::INTER_AREA);
  const int window = std::max(3, (kernel_px / shrink) | 1);
  cv::medianBlur(small, small_floor, window);
  cv::resize(small_floor, floor, grey.size(), 0.0, 0.0, cv::INTER_LINEAR);
  cv::Mat response;
  cv::subtract(grey, floor, response);  // saturates at 0
  return response;
}

// The grey level below which `share` of the image's pixels lie.
int Percentile(const cv::Mat& image, double share) {
  std::array<int, 256> histogram{};
  for (int r = 0; r < image.rows; ++r) {
    const std::uint8_t* p = image.ptr<std::uint8_t>(r);
    for (int c = 0; c < image.cols; ++c) ++histogram[p[c]];
  }
  const double target = share * static_cast<double>(image.total());
  double sum = 0.0;
  for (int v = 0; v < 256; ++v) {
    sum += histogram[static_cast<size_t>(v)];
    if (sum >= target) return v;
  }
  return 255;
}

// Centreline pixels of the paint: where the smoothed brightness above the
// floor peaks across the line, along x or along y (every line but a purely
// horizontal one peaks along x, and vice versa), by at least a quarter of
// the threshold within half the widest line.
cv::Mat Ridges(const cv::Mat& bright, const cv::Mat& paint, double max_width_px, double threshold) {
  cv::Mat smooth;
  const double sigma = std::max(1.0, max_width_px / 6.0);
  cv::GaussianBlur(bright, smooth, cv::Size(0, 0), sigma);
  const int r = static_cast<int>(std::ceil(max_width_px / 2));
  const cv::Mat kx = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * r + 1, 1));
  const cv::Mat ky = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(1, 2 * r + 1));
  cv::Mat max_x, min_x, max_y, min_y;
  cv::dilate(smooth, max_x, kx);
  cv::erode(smooth, min_x, kx);
  cv::dilate(smooth, max_y, ky);
  cv::erode(smooth, min_y, ky);
  const int drop = std::max(1, static_cast<int>(threshold / 4));
  cv::Mat ridges = cv::Mat::zeros(bright.size(), CV_8U);
  for (int y = 0; y < smooth.rows; ++y) {
    const std::uint8_t* v = smooth.ptr<std::uint8_t>(y);
    const std::uint8_t* ax = max_x.ptr<std::uint8_t>(y);
    const std::uint8_t* ix = min_x.ptr<std::uint8_t>(y);
    const std::uint8_t* ay = max_y.ptr<std::uint8_t>(y);
    const std::uint8_t* iy = min_y.ptr<std::uint8_t>(y);
    const std::uint8_t* m = paint.ptr<std::uint8_t>(y);
    std::uint8_t* out = ridges.ptr<std::uint8_t>(y);
    for (int x = 0; x < smooth.cols; ++x) {
      if (m[x] == 0) continue;
      const bool peak_x = v[x] == ax[x] && v[x] >= ix[x] + drop;
      const bool peak_y = v[x] == ay[x] && v[x] >= iy[x] + drop;
      if (peak_x || peak_y) out[x] = 255;
    }
  }
  return ridges;
}

// The brightness above the floor, less `floor`, across a line at `base`,
// sampled along `normal` within +-half_window_px: its sum, the offset of
// its centroid along `normal` (0 when there is none) and its peak.
struct CrossSection {
  double sum = 0.0, offset = 0.0, peak = 0.0;
};

CrossSection MeasureCrossSection(const cv::Mat& bright, const Eigen::Vector2d& base,
                                 const Eigen::Vector2d& normal, double half_window_px,
                                 double floor) {
  CrossSection c;
  double sum_s = 0.0;
  for (double s = -half_window_px; s <= half_window_px; s += 1.0) {
    const Eigen::Vector2d p = base + s * normal;
    const double v = Sample(bright, p.x(), p.y()) - floor;
    if (v <= 0.0) continue;
    c.sum += v;
    sum_s += v * s;
    c.peak = std::max(c.peak, v);
  }
  if (c.sum > 0.0) c.offset = sum_s / c.sum;
  return c;
}

// The least-squares line through points (at least two): their mean, and
// their principal direction signed to agree with `along`.
std::pair<Eigen::Vector2d, Eigen::Vector2d> FitLine(const std::vector<Eigen::Vector2d>& pts,
                                                    const Eigen::Vector2d& along) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : pts) mean += p;
  mean /= static_cast<double>(pts.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const Eigen::Vector2d& p : pts) scatter += (p - mean) * (p - mean).transpose();
  Eigen::Vector2d dir =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(scatter).eigenvectors().col(1);
  if (dir.dot(along) < 0) dir = -dir;
  return {mean, dir};
}

double Median(std::vector<double> values) {
  const auto middle = values.begin() + static_cast<long>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// One cross-section of a line: where along the rough line, the centroid
// of the response, its width (sum over peak) and peak.
struct LineSample {
  double t;
  Eigen::Vector2d centre;
  double width, peak;
};

// Grows a run of samples past both ends while the paint goes on, on the
// run's own axis and at its own width: a narrow cross-section centred on
// the axis, so that growth neither drifts with the rough direction nor
// bridges to paint beside the line. Gaps up to max_gap_px are crossed.
std::vector<LineSample> GrowRun(const cv::Mat& bright, const PaintLine& rough, double threshold,
                                double step_px, double max_gap_px, std::vector<LineSample> run) {
  std::vector<double> widths;
  std::vector<Eigen::Vector2d> centres;
  for (const LineSample& sample : run) {
    widths.push_back(sample.width);
    centres.push_back(sample.centre);
  }
  const double width = Median(widths);
  // Named copies rather than structured bindings: Clang before 16 cannot
  // capture bindings in the lambda below (a whole build with Debian 12's Clang).
  const auto axis = FitLine(centres, rough.dir);
  const Eigen::Vector2d axis_point = axis.first, axis_dir = axis.second;
  const Eigen::Vector2d axis_normal(-axis_dir.y(), axis_dir.x());
  const auto measure = [&](double t) -> std::optional<LineSample> {
    const Eigen::Vector2d on_rough = rough.point + t * rough.dir;
    const Eigen::Vector2d base = axis_point + (on_rough - axis_point).dot(axis_dir) * axis_dir;
    if (base.x() < 0 || base.y() < 0 || base.x() > bright.cols - 1 || base.y() > bright.rows - 1) {
      return std::nullopt;
    }
    const CrossSection c =
        MeasureCrossSection(bright, base, axis_normal, std::max(3.0, width), threshold / 2);
    if (c.peak < threshold / 2 || std::abs(c.offset) > std::max(1.5, width / 2) ||
        c.sum / c.peak > 1.5 * width) {
      return std::nullopt;
    }
    return LineSample{t, base + c.offset * axis_normal, c.sum / c.peak, c.peak};
  };
  for (double t = run.back().t + step_px; t - run.back().t <= max_gap_px; t += step_px) {
    if (const std::optional<LineSample> sample = measure(t)) run.push_back(*sample);
  }
  std::vector<LineSample> before;
  for (double t = run.front().t - step_px;
       (before.empty() ? run.front().t : before.back().t) - t <= max_gap_px; t -= step_px) {
    if (const std::optional<LineSample> sample = measure(t)) before.push_back(*sample);
  }
  run.insert(run.begin(), before.rbegin(), before.rend());
  return run;
}

// Paint is brighter than the floor on both sides; the bright side of a
// shadow's edge, a kerb or a lit patch is not. The share of the centres
// (of the grey image) that stand above both sides, one line width out
// along `normal`, by at least half their contrast over the darker side.
// Painted digits or other lines beside a line hide one side in places, not
// along the whole line. 1 when there is no centre.
double TwoSidedShare(const cv::Mat& grey, const std::vector<Eigen::Vector2d>& centres,
                     const Eigen::Vector2d& normal, double width_px) {
  const double out = std::max(3.0, width_px);
  int two_sided = 0;
  for (const Eigen::Vector2d& c : centres) {
    const Eigen::Vector2d l = c + out * normal, r = c - out * normal;
    const double centre = Sample(grey, c.x(), c.y());
    const double left = centre - Sample(grey, l.x(), l.y());
    const double right = centre - Sample(grey, r.x(), r.y());
    if (std::max(left, right) > 0.0 && std::min(left, right) >= 0.5 * std::max(left, right)) {
      ++two_sided;
    }
  }
  return centres.empty() ? 1.0 : static_cast<double>(two_sided) / centres.size();
}

// The support threshold of a rough line: line_share of its own median peak
// over its rough extent, within [min_threshold, global_threshold].
double LineThreshold(const cv::Mat& bright, const PaintLine& line, const Eigen::Vector2d& normal,
                     double global_threshold, double min_threshold, double line_share,
                     double half_window_px, double step_px) {
  std::vector<double> peaks;
  for (double t = line.t0; t <= line.t1; t += step_px) {
    const Eigen::Vector2d base = line.point + t * line.dir;
    peaks.push_back(MeasureCrossSection(bright, base, normal, half_window_px, 0.0).peak);
  }
  if (peaks.empty()) return global_threshold;
  return std::clamp(line_share * Median(peaks), min_threshold, global_threshold);
}

// The longest run of samples (in t order) no further apart than max_gap.
std::vector<LineSample> LongestRun(const std::vector<LineSample>& support, double max_gap) {
  size_t best_begin = 0, best_end = 0;
  for (size_t begin = 0; begin < support.size();) {
    size_t end = begin + 1;
    while (end < support.size() && support[end].t - support[end - 1].t <= max_gap) ++end;
    if (end - begin > best_end - best_begin) best_begin = begin, best_end = end;
    begin = end;
  }
  return std::vector<LineSample>(support.begin() + static_cast<long>(best_begin),
                                 support.begin() + static_cast<long>(best_end));
}

// Refines a rough line on the brightness above the floor (`bright`):
// centroids of the response across the line at regular steps give the
// centreline by least squares; the painted extent is where the response
// holds. Support is measured against global_threshold or, for a faint line
// (worn paint, shadow), against line_share of its own median peak over its
// rough extent, whichever is lower but not below min_threshold. Returns
// false when too little of the line is supported.
bool RefineLine(const cv::Mat& grey, const cv::Mat& bright, double global_threshold,
                double min_threshold, double line_share, double half_window_px,
                double min_length_px, PaintLine* line) {
  constexpr double kStepPx = 2.0;
  // The widest gap within one line's run: narrower than a line's width.
  constexpr double kMaxGapPx = 3 * kStepPx;
  const Eigen::Vector2d normal(-line->dir.y(), line->dir.x());
  const double threshold = LineThreshold(bright, *line, normal, global_threshold, min_threshold,
                                         line_share, half_window_px, kStepPx);
  // Search a little beyond the rough ends: the skeleton stops short of
  // them.
  const double margin = 2.0 * half_window_px;
  std::vector<LineSample> support;
  for (double t = line->t0 - margin; t <= line->t1 + margin; t += kStepPx) {
    const Eigen::Vector2d base = line->point + t * line->dir;
    if (base.x() < 0 || base.y() < 0 || base.x() > bright.cols - 1 || base.y() > bright.rows - 1) {
      continue;
    }
    const CrossSection c = MeasureCrossSection(bright, base, normal, half_window_px, threshold / 2);
    if (c.peak < threshold / 2) continue;
    support.push_back({t, base + c.offset * normal, c.sum / c.peak, c.peak});
  }
  if (support.size() < 4) return false;
  // Longest run of supported samples, grown on while the paint goes on:
  // the Hough transform cuts a real line into pieces where its paint is
  // worn or its width changes.
  const std::vector<LineSample> run =
      GrowRun(bright, *line, threshold, kStepPx, kMaxGapPx, LongestRun(support, kMaxGapPx));
  const double t_lo = run.front().t, t_hi = run.back().t;
  if (t_hi - t_lo < min_length_px) return false;
  // Fit on the interior (the ends are disturbed by crossing lines), twice,
  // dropping outliers the second time.
  std::vector<double> widths, peaks;
  for (const LineSample& sample : run) {
    widths.push_back(sample.width);
    peaks.push_back(sample.peak);
  }
  const double width = Median(widths);
  Eigen::Vector2d point = line->point, dir = line->dir;
  std::vector<Eigen::Vector2d> interior;
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<Eigen::Vector2d> pts;
    for (const LineSample& sample : run) {
      if (sample.t < t_lo + width || sample.t > t_hi - width) continue;
      if (pass == 0) interior.push_back(sample.centre);
      // Wide cross-sections run along a crossing line: their centroid is
      // pulled sideways.
      if (sample.width > 1.3 * width) continue;
      if (pass == 1 && std::abs(Cross(dir, sample.centre - point)) > 1.5) continue;
      pts.push_back(sample.centre);
    }
    if (pts.size() < 3) {
      if (pass == 0) return false;
      break;
    }
    std::tie(point, dir) = FitLine(pts, line->dir);
  }
  const Eigen::Vector2d lo = line->point + t_lo * line->dir, hi = line->point + t_hi * line->dir;
  line->point = point;
  line->dir = dir;
  line->t0 = (lo - point).dot(dir);
  line->t1 = (hi - point).dot(dir);
  line->width_px = width;
  line->contrast = Median(peaks) + threshold / 2;
  line->two_sided_share = TwoSidedShare(grey, interior, Eigen::Vector2d(-dir.y(), dir.x()), width);
  return true;
}

// Merges Hough segments of one painted line: same direction, close to one
// another's line, overlapping or nearly so along it.
std::vector<PaintLine> MergeSegments(const std::vector<cv::Vec4i>& segments, double max_offset_px,
                                     double max_gap_px) {
  struct Seg {
    Eigen::Vector2d a, b;
    double length;
  };
  std::vector<Seg> segs;
  for (const cv::Vec4i& s : segments) {
    const Eigen::Vector2d a(s[0], s[1]), b(s[2], s[3]);
    segs.push_back({a, b, (b - a).norm()});
  }
  std::sort(segs.begin(), segs.end(),
            [](const Seg& x, const Seg& y) { return x.length > y.length; });
  std::vector<PaintLine> lines;
  constexpr double kMaxAngle = 0.09;  // about 5 degrees
  for (const Seg& s : segs) {
    if (s.length <= 0.0) continue;
    const Eigen::Vector2d d = (s.b - s.a) / s.length;
    bool merged = false;
    for (PaintLine& line : lines) {
      if (std::abs(Cross(line.dir, d)) > kMaxAngle) continue;
      if (std::abs(line.Across(s.a)) > max_offset_px || std::abs(line.Across(s.b)) > max_offset_px)
        continue;
      const double ta = line.Along(s.a), tb = line.Along(s.b);
      const double lo = std::min(ta, tb), hi = std::max(ta, tb);
      if (lo > line.t1 + max_gap_px || hi < line.t0 - max_gap_px) continue;
      line.t0 = std::min(line.t0, lo);
      line.t1 = std::max(line.t1, hi);
      merged = true;
      break;
    }
    if (merged) continue;
    PaintLine line;
    line.point = s.a;
    line.dir = d;
    line.t0 = 0.0;
    line.t1 = s.length;
    lines.push_back(line);
  }
  return lines;
}

// Share of paint around a junction that belongs to none of its arms: a
// ring of samples at radii between one line width and two arms' length.
// Junctions inside painted digits, or among texture, sit in clutter; the
// corner of a slot stands alone.
double Clutter(const cv::Mat& paint, const Eigen::Vector2d& x,
               const std::vector<Eigen::Vector2d>& arms, double width_px, double min_arm_px) {
  constexpr int kAngles = 72;
  int samples = 0, stray = 0;
  for (double r = width_px + 2.0; r <= min_arm_px; r += 3.0) {
    const double half_angle = std::atan2(width_px / 2 + 2.5, r);
    for (int k = 0; k < kAngles; ++k) {
      const double a = 2 * kPi * k / kAngles;
      const Eigen::Vector2d d(std::cos(a), std::sin(a));
      const Eigen::Vector2d p = x + r * d;
      const int px = static_cast<int>(std::lround(p.x())),
                py = static_cast<int>(std::lround(p.y()));
      if (px < 0 || py < 0 || px >= paint.cols || py >= paint.rows) continue;
      ++samples;
      if (paint.at<std::uint8_t>(py, px) == 0) continue;
      bool on_arm = false;
      for (const Eigen::Vector2d& arm : arms) {
        if (std::acos(std::clamp(arm.dot(d), -1.0, 1.0)) <= half_angle) on_arm = true;
      }
      if (!on_arm) ++stray;
    }
  }
  return samples > 0 ? static_cast<double>(stray) / samples : 1.0;
}

// Share of samples on paint along p + t dir, t in [from_px, to_px].
double PaintAlong(const cv::Mat& paint, const Eigen::Vector2d& p, const Eigen::Vector2d& dir,
                  double from_px, double to_px) {
  int samples = 0, on = 0;
  for (double t = from_px; t <= to_px; t += 1.0) {
    const Eigen::Vector2d q = p + t * dir;
    const int x = static_cast<int>(std::lround(q.x())), y = static_cast<int>(std::lround(q.y()));
    if (x < 0 || y < 0 || x >= paint.cols || y >= paint.rows) continue;
    ++samples;
    if (paint.at<std::uint8_t>(y, x) != 0) ++on;
  }
  return samples > 0 ? static_cast<double>(on) / samples : 0.0;
}

// An L corner from the long line and the stub's centreline measured near
// the corner only: cross-section centroids along the stub out to one arm's
// length, fitted by least squares, twice (the second time along the first
// fit's direction). Empty when the stub is not found.
std::optional<Eigen::Vector2d> RefineCorner(const cv::Mat& bright, double threshold,
                                            const Eigen::Vector2d& corner,
                                            const PaintLine& long_line, Eigen::Vector2d stub,
                                            double width_px, double arm_px) {
  Eigen::Vector2d x = corner;
  for (int pass = 0; pass < 2; ++pass) {
    const Eigen::Vector2d normal(-stub.y(), stub.x());
    std::vector<Eigen::Vector2d> pts;
    for (double t = width_px; t <= arm_px; t += 2.0) {
      const Eigen::Vector2d base = x + t * stub;
      const CrossSection c = MeasureCrossSection(bright, base, normal, width_px, threshold / 2);
      if (c.sum > 0.0) pts.push_back(base + c.offset * normal);
    }
    if (pts.size() < 4) return std::nullopt;
    const auto [mean, d] = FitLine(pts, stub);
    // Intersection of the long line with mean + u d.
    const double sin_ld = Cross(long_line.dir, d);
    if (std::abs(sin_ld) < 0.3) return std::nullopt;
    const double u = Cross(long_line.point - mean, long_line.dir) / -sin_ld;
    x = mean + u * d;
    stub = d;
  }
  if ((x - corner).norm() > arm_px) return std::nullopt;
  return x;
}

struct Junction {
  MarkingPoint point;
  // The arm of an L junction not taken as its separating line, and its
  // length in view.
  double other_direction_rad = 0.0;
  double other_arm_px = 0.0;
};

double PointDistanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                              const Eigen::Vector2d& b, double* along) {
  const Eigen::Vector2d ab = b - a;
  const double u = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  if (along != nullptr) *along = u;
  return (p - (a + u * ab)).norm();
}

// Whether a line at least min_length_px long, at least asin(min_sin) across
// the segment p-q, ends within tolerance_px of it in its middle 60 % and
// leaves it towards `side`.
bool LineEndsBetween(const std::vector<PaintLine>& lines, const Eigen::Vector2d& p,
                     const Eigen::Vector2d& q, const Eigen::Vector2d& side, double min_length_px,
                     double min_sin, double tolerance_px) {
  const Eigen::Vector2d pq = (q - p).normalized();
  for (const PaintLine& line : lines) {
    if (line.length() < min_length_px || std::abs(Cross(pq, line.dir)) < min_sin) continue;
    for (const double t : {line.t0, line.t1}) {
      const Eigen::Vector2d leaving = t == line.t0 ? line.dir : Eigen::Vector2d(-line.dir);
      double along = 0.0;
      const double dist = PointDistanceToSegment(line.point + t * line.dir, p, q, &along);
      if (dist < tolerance_px && along > 0.2 && along < 0.8 && leaving.dot(side) > 0.0) {
        return true;
      }
    }
  }
  return false;
}

}  // namespace

const char* ToString(MarkingShape shape) { return shape == MarkingShape::kT ? "T" : "L"; }

bool SlotDetectorOptions::IsValid(std::string* error) const {
  FieldChecker c(error);
  c.Between(pixels_per_m, 1.0, 1000.0, "pixels_per_m", "px/m");
  c.Between(min_line_width_m, 0.0, 1.0, "min_line_width_m", "m");
  c.Between(max_line_width_m, min_line_width_m, 1.0, "max_line_width_m", "m");
  c.Positive(min_entrance_m, "min_entrance_m");
  c.Require(max_entrance_m > min_entrance_m, "max_entrance_m",
            "must be greater than min_entrance_m");
  c.Between(parallel_min_entrance_m, 0.0, 100.0, "parallel_min_entrance_m", "m");
  c.Positive(standard_depth_m, "standard_depth_m");
  c.Positive(parallel_depth_m, "parallel_depth_m");
  c.Between(max_direction_difference_rad, 0.0, kPi / 2, "max_direction_difference_rad", "rad");
  c.Positive(on_line_tolerance_m, "on_line_tolerance_m");
  c.Positive(min_arm_m, "min_arm_m");
  c.Require(min_stem_m >= min_arm_m, "min_stem_m", "must be at least min_arm_m");
  c.NonNegative(max_merge_gap_m, "max_merge_gap_m");
  c.PositiveAtMost(max_clutter, 1.0, "max_clutter", "");
  c.Positive(long_line_m, "long_line_m");
  c.Positive(max_width_deviation, "max_width_deviation");
  c.InRange(min_contrast_grey, 1.0, 255.0, "min_contrast_grey", "");
  c.AtLeast(local_contrast_factor, 1.0, "local_contrast_factor");
  c.Positive(local_window_m, "local_window_m");
  c.Between(min_junction_angle_rad, 0.0, kPi / 2, "min_junction_angle_rad", "rad");
  c.PositiveAtMost(relative_contrast, 1.0, "relative_contrast", "");
  c.PositiveAtMost(line_relative_contrast, 1.0, "line_relative_contrast", "");
  c.Rate(min_two_sided_share, "min_two_sided_share");
  c.Require(mask_margin_m >= 0.0 && mask_margin_m < 1.0, "mask_margin_m", "must be in [0, 1) m");
  c.AtLeast(max_lines_nearby, 0, "max_lines_nearby");
  c.Positive(nearby_radius_m, "nearby_radius_m");
  c.NonNegative(end_tolerance_px, "end_tolerance_px");
  c.Require(max_vehicle_depth_in_row_m >= 0.0 && max_vehicle_depth_in_row_m <= 100.0,
            "max_vehicle_depth_in_row_m", "must be in [0, 100] m");
  return c.ok();
}

// The car stands at `centre_px`; a slot opening away from it is the usual
// case. One opening towards it has the car on its interior side of the
// entrance line: inside its row if the car is less than
// max_vehicle_depth_m past that line, else beyond its far end.
bool SlotOpensAsAllowed(const Eigen::Vector2d& a_px, const Eigen::Vector2d& b_px,
                        const Eigen::Vector2d& depth_dir, const Eigen::Vector2d& centre_px,
                        double pixels_per_m, bool parallel, bool require_facing,
                        double max_vehicle_depth_m) {
  const double vehicle_depth_px = depth_dir.dot(centre_px - (a_px + b_px) / 2);
  if (!require_facing || vehicle_depth_px <= 0.0) return true;
  return !parallel && vehicle_depth_px < max_vehicle_depth_m * pixels_per_m;
}

SlotDetector::SlotDetector(const SlotDetectorOptions& options) : options_(options) {
  std::string error;
  if (!options_.IsValid(&error)) throw std::invalid_argument("slot detector: " + error);
}

namespace {

// Grey levels at or below this are what no camera saw (fused top views
// paint the car's footprint pure black).
constexpr int kUnseenGrey = 2;
// Unseen regions are at least this wide (px): single black pixels are not.
constexpr int kUnseenOpeningPx = 9;
// The brightest paint in view: this quantile of the brightness above the
// floor.
constexpr double kBrightestPaintQuantile = 0.995;
// The probabilistic Hough transform on the ridges: votes and the shortest
// piece as shares of the shortest arm, the largest gap within a piece as a
// share of the widest line.
constexpr double kHoughVotesPerArm = 0.6;
constexpr double kHoughMinPiecePerArm = 0.7;
constexpr double kHoughMaxGapPerWidth = 0.5;
// A refined line's width must lie in [this x the narrowest line,
// this x the widest line].
constexpr double kMinWidthShare = 0.5;
constexpr double kMaxWidthShare = 1.5;
// Two refined lines are one when this parallel (sine of the angle between
// them) and their centrelines this close (px).
constexpr double kSameLineSin = 0.05;
constexpr double kSameLineOffsetPx = 3.0;
// A marking point's score: the weaker line's contrast over this many times
// the paint threshold, clamped to [0, 1].
constexpr double kFullScoreContrasts = 3.0;
// An entrance line's arm leaves a point within 45 degrees of its partner,
// with paint along at least this share of an arm's length.
constexpr double kCos45 = 0.7071;
constexpr double kMinEntrancePaintShare = 0.5;
// Two directions closer than this are the same arm.
constexpr double kSameDirectionRad = 1e-9;

// What every stage of one detection shares: the options, pixel scales of
// them, and the images.
struct Frame {
  Frame(const SlotDetectorOptions& options)
      : o(options),
        s(options.pixels_per_m),
        max_width_px(options.max_line_width_m * s),
        min_arm_px(options.min_arm_m * s),
        min_stem_px(options.min_stem_m * s),
        min_sin(std::sin(options.min_junction_angle_rad)) {}

  const SlotDetectorOptions& o;
  const double s;  // pixels per metre
  const double max_width_px, min_arm_px, min_stem_px, min_sin;
  cv::Mat grey;   // masked pixels set to the mean of the rest
  cv::Mat valid;  // empty: all; else non-zero where lines may be found
  cv::Mat bright;
  double threshold = 0.0;  // paint brightness above the floor
  cv::Mat paint;
};

// 0. The grey image, and what may be searched: fused top views paint what
//    no camera sees (the car's footprint) pure black; regions of it are
//    masked like the given mask. Masked pixels take the mean of the rest,
//    so that their border makes no edge; a margin of mask_margin_m is
//    ignored around them.
void PrepareImage(const cv::Mat& top_view, const cv::Mat& mask, Frame* f) {
  if (top_view.channels() == 3) {
    cv::cvtColor(top_view, f->grey, cv::COLOR_BGR2GRAY);
  } else {
    f->grey = top_view.clone();
  }
  cv::Mat seen;
  cv::Mat unseen = f->grey <= kUnseenGrey;
  cv::morphologyEx(
      unseen, unseen, cv::MORPH_OPEN,
      cv::getStructuringElement(cv::MORPH_RECT, cv::Size(kUnseenOpeningPx, kUnseenOpeningPx)));
  if (cv::countNonZero(unseen) > 0) {
    seen = unseen == 0;
    if (!mask.empty()) seen &= mask;
  } else {
    seen = mask;
  }
  if (seen.empty()) return;
  f->grey.setTo(cv::mean(f->grey, seen), seen == 0);
  cv::erode(seen, f->valid, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)),
            cv::Point(-1, -1), static_cast<int>(std::ceil(f->o.mask_margin_m * f->s)));
}

// 1. Paint: the brightness above the floor's median over twice the widest
//    line. A pixel is paint when it stands local_contrast_factor times above
//    the mean response around it (so that textured floor, grass or a car's
//    body, whose response is high everywhere, is not) and above
//    min_contrast_grey. Line refinement measures support against a
//    threshold relative to the brightest paint in view, or to the line's
//    own contrast for a faint line.
void FindPaint(Frame* f) {
  const SlotDetectorOptions& o = f->o;
  const int kernel_px = 2 * static_cast<int>(std::ceil(f->max_width_px)) + 1;
  f->bright = BrightAboveFloor(f->grey, kernel_px);
  f->threshold = std::max(o.min_contrast_grey,
                          o.relative_contrast * Percentile(f->bright, kBrightestPaintQuantile));
  const int window_px = 2 * static_cast<int>(std::lround(o.local_window_m * f->s / 2)) + 1;
  cv::Mat local_mean, response;
  cv::boxFilter(f->bright, local_mean, CV_32F, cv::Size(window_px, window_px));
  f->bright.convertTo(response, CV_32F);
  f->paint = (response > local_mean * o.local_contrast_factor) & (f->bright > o.min_contrast_grey);
  if (!f->valid.empty()) f->paint.setTo(0, f->valid == 0);
}

// Refinement may make two rough pieces one line: a line parallel to an
// earlier one, on its centreline and overlapping it along it, extends that
// one instead. True when it did.
bool ExtendsAnEarlierLine(const PaintLine& line, std::vector<PaintLine>* lines) {
  for (PaintLine& other : *lines) {
    if (std::abs(Cross(other.dir, line.dir)) >= kSameLineSin ||
        std::abs(other.Across(line.point + (line.t0 + line.t1) / 2 * line.dir)) >=
            kSameLineOffsetPx) {
      continue;
    }
    const double a0 = other.Along(line.point + line.t0 * line.dir);
    const double a1 = other.Along(line.point + line.t1 * line.dir);
    const double lo = std::min(a0, a1), hi = std::max(a0, a1);
    if (lo < other.t1 && hi > other.t0) {
      other.t0 = std::min(other.t0, lo);
      other.t1 = std::max(other.t1, hi);
      return true;
    }
  }
  return false;
}

// 2. Centrelines: the ridges of the paint, their straight pieces by the
//    probabilistic Hough transform, merged per painted line and refined on
//    the brightness above the floor.
std::vector<PaintLine> FindLines(const Frame& f) {
  const SlotDetectorOptions& o = f.o;
  const cv::Mat ridges = Ridges(f.bright, f.paint, f.max_width_px, f.threshold);
  std::vector<cv::Vec4i> segments;
  cv::HoughLinesP(ridges, segments, 1.0, kPi / 180.0,
                  static_cast<int>(f.min_arm_px * kHoughVotesPerArm),
                  f.min_arm_px * kHoughMinPiecePerArm, f.max_width_px * kHoughMaxGapPerWidth);
  // Pieces merge across gaps narrower than the gap between painted digits.
  std::vector<PaintLine> rough =
      MergeSegments(segments, f.max_width_px / 2, o.max_merge_gap_m * f.s);
  std::vector<PaintLine> lines;
  for (PaintLine& line : rough) {
    if (!RefineLine(f.grey, f.bright, f.threshold, o.min_contrast_grey, o.line_relative_contrast,
                    f.max_width_px, f.min_arm_px, &line)) {
      continue;
    }
    if (line.width_px < o.min_line_width_m * f.s * kMinWidthShare ||
        line.width_px > f.max_width_px * kMaxWidthShare)
      continue;
    if (line.two_sided_share < o.min_two_sided_share) continue;
    if (!ExtendsAnEarlierLine(line, &lines)) lines.push_back(line);
  }
  return lines;
}

// The lot's lines are painted alike: the median width of the long lines
// (surely slot lines) is the width a junction's lines must have; 0 when
// fewer than two long lines are in view.
double TypicalLineWidth(const Frame& f, const std::vector<PaintLine>& lines) {
  std::vector<double> long_widths;
  for (const PaintLine& line : lines) {
    if (line.length() >= f.o.long_line_m * f.s) long_widths.push_back(line.width_px);
  }
  return long_widths.size() >= 2 ? Median(long_widths) : 0.0;
}

// Where a line stands relative to the junction at t along it: -1 ends there
// at its start, +1 ends there at its end, 0 passes through with arms on both
// sides; false: no junction. A line overshooting the junction by less than
// tol (its paint runs through the other line's width, more so at acute
// angles) ends there too.
bool ClassifyEnd(const PaintLine& l, double t, double tol, double min_arm_px, int* where) {
  const double minus = t - l.t0, plus = l.t1 - t;
  if (minus >= min_arm_px && plus >= min_arm_px) return *where = 0, true;
  if (plus >= min_arm_px && minus >= -tol) return *where = -1, true;
  if (minus >= min_arm_px && plus >= -tol) return *where = 1, true;
  return false;
}

// The lines other than i and j whose paint passes within nearby_radius_m.
int LinesNearby(const Frame& f, const std::vector<PaintLine>& lines, size_t i, size_t j,
                const Eigen::Vector2d& px) {
  int nearby = 0;
  for (size_t k = 0; k < lines.size(); ++k) {
    if (k == i || k == j) continue;
    const Eigen::Vector2d ka = lines[k].point + lines[k].t0 * lines[k].dir;
    const Eigen::Vector2d kb = lines[k].point + lines[k].t1 * lines[k].dir;
    if (PointDistanceToSegment(px, ka, kb, nullptr) < f.o.nearby_radius_m * f.s) ++nearby;
  }
  return nearby;
}

// One line at a junction: where it stands (ClassifyEnd), its arm's length
// and direction away from the junction.
struct JunctionArm {
  const PaintLine* line;
  int where;
  double arm_px;
  Eigen::Vector2d dir;
};

// The marking point at x of two lines: a T (one passes through) points
// along the other, the stem; an L along its longer arm, the shorter kept
// for pairing, its corner refitted next to the junction.
Junction ShapeJunction(const Frame& f, const JunctionArm& a, const JunctionArm& b,
                       const Eigen::Vector2d& x) {
  Junction junction;
  junction.point.px = x;
  junction.point.score = std::clamp(
      std::min(a.line->contrast, b.line->contrast) / (kFullScoreContrasts * f.threshold), 0.0, 1.0);
  if (a.where == 0 || b.where == 0) {
    const Eigen::Vector2d& stem = a.where != 0 ? a.dir : b.dir;
    junction.point.shape = MarkingShape::kT;
    junction.point.direction_rad = std::atan2(stem.y(), stem.x());
    junction.other_direction_rad = junction.point.direction_rad;
    return junction;
  }
  junction.point.shape = MarkingShape::kL;
  const JunctionArm& main = a.arm_px >= b.arm_px ? a : b;
  const JunctionArm& other = a.arm_px >= b.arm_px ? b : a;
  junction.point.direction_rad = std::atan2(main.dir.y(), main.dir.x());
  junction.other_direction_rad = std::atan2(other.dir.y(), other.dir.x());
  junction.other_arm_px = std::min(a.arm_px, b.arm_px);
  // The stub's line, fitted over its whole length, can be pulled askew by
  // paint beyond it (a digit); refit it next to the corner.
  if (const std::optional<Eigen::Vector2d> refined = RefineCorner(
          f.bright, f.threshold, x, *main.line, other.dir, main.line->width_px, f.min_arm_px)) {
    junction.point.px = *refined;
  }
  return junction;
}

// The marking point where lines i and j meet, if they make one.
std::optional<Junction> JunctionOf(const Frame& f, const std::vector<PaintLine>& lines, size_t i,
                                   size_t j, double typical_width_px) {
  const SlotDetectorOptions& o = f.o;
  const PaintLine& a = lines[i];
  const PaintLine& b = lines[j];
  const double sin_ab = Cross(a.dir, b.dir);
  if (std::abs(sin_ab) < f.min_sin) return std::nullopt;
  // Long lines are slot lines whatever their width (it grows with blur far
  // from the car); short ones must look like them. A short line meeting a
  // long one passes as well when their widths agree (the lot's line width
  // varies with blur across a real view).
  const auto width_ok = [&](const PaintLine& line) {
    return typical_width_px <= 0.0 || line.length() >= o.long_line_m * f.s ||
           std::abs(line.width_px - typical_width_px) <= o.max_width_deviation * typical_width_px;
  };
  const bool alike = std::max(a.width_px, b.width_px) <=
                         (1.0 + o.max_width_deviation) * std::min(a.width_px, b.width_px) &&
                     std::max(a.length(), b.length()) >= o.long_line_m * f.s;
  if (!(width_ok(a) && width_ok(b)) && !alike) return std::nullopt;
  // Intersection: a.point + ta a.dir = b.point + tb b.dir.
  const Eigen::Vector2d d = b.point - a.point;
  const double ta = Cross(d, b.dir) / sin_ab;
  const double tb = Cross(d, a.dir) / sin_ab;
  const Eigen::Vector2d x = a.point + ta * a.dir;
  if (x.x() < 0 || x.y() < 0 || x.x() > f.grey.cols - 1 || x.y() > f.grey.rows - 1) {
    return std::nullopt;
  }
  const double tol_a = 0.5 * b.width_px / std::abs(sin_ab) + o.end_tolerance_px;
  const double tol_b = 0.5 * a.width_px / std::abs(sin_ab) + o.end_tolerance_px;
  int wa = 0, wb = 0;
  if (!ClassifyEnd(a, ta, tol_a, f.min_arm_px, &wa) ||
      !ClassifyEnd(b, tb, tol_b, f.min_arm_px, &wb)) {
    return std::nullopt;
  }
  if (wa == 0 && wb == 0) return std::nullopt;  // a crossing, not a junction
  // Arm lengths from the junction; one arm (the separating line) must be
  // long: painted digits make short strokes only.
  const double arm_a = wa < 0 ? a.t1 - ta : (wa > 0 ? ta - a.t0 : 0.0);
  const double arm_b = wb < 0 ? b.t1 - tb : (wb > 0 ? tb - b.t0 : 0.0);
  if (std::max(arm_a, arm_b) < f.min_stem_px) return std::nullopt;
  const Eigen::Vector2d dir_a = wa <= 0 ? a.dir : Eigen::Vector2d(-a.dir);
  const Eigen::Vector2d dir_b = wb <= 0 ? b.dir : Eigen::Vector2d(-b.dir);
  if ((wa != 0 && wb == 0 && arm_a < f.min_stem_px) ||
      (wa == 0 && wb != 0 && arm_b < f.min_stem_px)) {
    return std::nullopt;  // a T's stem must be long
  }
  Junction junction = ShapeJunction(f, {&a, wa, arm_a, dir_a}, {&b, wb, arm_b, dir_b}, x);
  if (!f.valid.empty()) {
    const int cx = static_cast<int>(std::lround(x.x())), cy = static_cast<int>(std::lround(x.y()));
    if (f.valid.at<std::uint8_t>(cy, cx) == 0) return std::nullopt;
  }
  std::vector<Eigen::Vector2d> arms{dir_a, dir_b};
  if (wa == 0) arms.push_back(-dir_a);
  if (wb == 0) arms.push_back(-dir_b);
  const double clutter =
      Clutter(f.paint, junction.point.px, arms, std::max(a.width_px, b.width_px), f.min_arm_px);
  if (clutter > o.max_clutter) return std::nullopt;
  // A slot's corner has few lines around it; a car's body, grass or a
  // textured wall make many.
  if (LinesNearby(f, lines, i, j, junction.point.px) > o.max_lines_nearby) return std::nullopt;
  return junction;
}

// 3. Marking points (paper III-A, Fig. 3): where one line ends on another.
//    A line ending in the middle of another makes a T, two lines ending
//    together an L. The direction is the line leaving the junction (for an
//    L the longer arm; the other one is kept for pairing).
std::vector<Junction> FindJunctions(const Frame& f, const std::vector<PaintLine>& lines) {
  const double typical_width_px = TypicalLineWidth(f, lines);
  std::vector<Junction> junctions;
  for (size_t i = 0; i < lines.size(); ++i) {
    for (size_t j = i + 1; j < lines.size(); ++j) {
      if (std::optional<Junction> junction = JunctionOf(f, lines, i, j, typical_width_px)) {
        junctions.push_back(*junction);
      }
    }
  }
  return junctions;
}

// Non-maximum suppression: one marking point per junction, T before L, the
// higher score first; within min_arm_m of a kept one a point is dropped.
std::vector<Junction> SuppressNonMaxima(const Frame& f, std::vector<Junction> junctions) {
  std::sort(junctions.begin(), junctions.end(), [](const Junction& x, const Junction& y) {
    if (x.point.shape != y.point.shape) return x.point.shape == MarkingShape::kT;
    return x.point.score > y.point.score;
  });
  std::vector<Junction> kept;
  const double nms_px = f.o.min_arm_m * f.s;
  for (const Junction& junction : junctions) {
    bool near = false;
    for (const Junction& k : kept) {
      if ((k.point.px - junction.point.px).norm() < nms_px) near = true;
    }
    if (!near) kept.push_back(junction);
  }
  return kept;
}

// 4. Entrance lines (paper III-A): pairs of marking points at a slot's
//    width whose separating lines leave to the same side, in the same
//    direction. Candidates with a third marking point on them, or of
//    implausible length, are removed.
class EntrancePairing {
 public:
  EntrancePairing(const Frame& f, const std::vector<PaintLine>& lines,
                  const std::vector<Junction>& points)
      : f_(f), lines_(lines), points_(points) {}

  // The slot whose entrance runs from point i to point j, if any.
  std::optional<DetectedSlot> SlotOf(size_t i, size_t j) const {
    const SlotDetectorOptions& o = f_.o;
    const MarkingPoint& pi = points_[i].point;
    const MarkingPoint& pj = points_[j].point;
    const Eigen::Vector2d e = pj.px - pi.px;
    const double length_m = e.norm() / f_.s;
    if (length_m < o.min_entrance_m || length_m > o.max_entrance_m) return std::nullopt;
    Eigen::Vector2d dir_i, dir_j;
    if (!SeparatingLines(i, j, e, &dir_i, &dir_j)) return std::nullopt;
    const Eigen::Vector2d depth_dir = (dir_i + dir_j).normalized();
    // The slot opens towards the car: its interior lies beyond the
    // entrance as seen from the image centre.
    const Eigen::Vector2d centre_px((f_.grey.cols - 1) / 2.0, (f_.grey.rows - 1) / 2.0);
    if (!SlotOpensAsAllowed(pi.px, pj.px, depth_dir, centre_px, f_.s,
                            length_m >= o.parallel_min_entrance_m,
                            o.require_entrance_facing_vehicle, o.max_vehicle_depth_in_row_m)) {
      return std::nullopt;
    }
    if (ThirdPointOn(i, j)) return std::nullopt;
    // A parallel slot's entrance is as long as two perpendicular slots'
    // entrances: where the corner between two of those was missed, its
    // separating line still ends on the candidate between the two points.
    if (length_m >= o.parallel_min_entrance_m &&
        LineEndsBetween(lines_, pi.px, pj.px, depth_dir, f_.min_stem_px, f_.min_sin,
                        o.on_line_tolerance_m * f_.s)) {
      return std::nullopt;
    }
    DetectedSlot slot;
    // Corner order: walking from corner 0 to corner 1 the slot lies on the
    // left in the vehicle frame, which the top view mirrors: on the right
    // on screen, Cross(p1 - p0, depth) < 0.
    const bool i_first = Cross(e, depth_dir) < 0.0;
    const size_t first = i_first ? i : j, second = i_first ? j : i;
    const double depth_m =
        length_m >= o.parallel_min_entrance_m ? o.parallel_depth_m : o.standard_depth_m;
    const Eigen::Vector2d& p_first = points_[first].point.px;
    const Eigen::Vector2d& p_second = points_[second].point.px;
    slot.corners_px[0] = p_first;
    slot.corners_px[1] = p_second;
    slot.corners_px[2] = p_second + depth_m * f_.s * depth_dir;
    slot.corners_px[3] = p_first + depth_m * f_.s * depth_dir;
    slot.depth_dir_px = depth_dir;
    slot.marking_points = {static_cast<int>(first), static_cast<int>(second)};
    slot.confidence = std::sqrt(pi.score * pj.score);
    return slot;
  }

 private:
  // The arm of point k not used as its separating line (an L's other arm;
  // a T's through line) is its stretch of the entrance line: it must
  // point to the partner, with paint along most of an arm's length.
  bool EntranceArmOk(size_t k, double used, const Eigen::Vector2d& to_partner) const {
    const Junction& p = points_[k];
    if (p.point.shape == MarkingShape::kL) {
      const double unused = std::abs(AngleDiff(used, p.point.direction_rad)) < kSameDirectionRad
                                ? p.other_direction_rad
                                : p.point.direction_rad;
      if (Eigen::Vector2d(std::cos(unused), std::sin(unused)).dot(to_partner) < kCos45) {
        return false;
      }
    }
    return PaintAlong(f_.paint, p.point.px, to_partner, 0.5 * f_.max_width_px, f_.min_arm_px) >=
           kMinEntrancePaintShare;
  }

  // The separating line is a stem (at least min_stem_m in view), also where
  // an L's shorter arm is taken as it: the short strokes at both ends of a
  // row's end line make no parallel slot.
  bool ShortArmUsed(size_t k, double used) const {
    const Junction& p = points_[k];
    return p.point.shape == MarkingShape::kL &&
           std::abs(AngleDiff(used, p.point.direction_rad)) > kSameDirectionRad &&
           p.other_arm_px < f_.min_stem_px;
  }

  // Each point may use either arm of an L as its separating line: the first
  // choice whose lines agree in direction, are stems, leave room for the
  // entrance line and leave it (not run along it).
  bool SeparatingLines(size_t i, size_t j, const Eigen::Vector2d& e, Eigen::Vector2d* dir_i,
                       Eigen::Vector2d* dir_j) const {
    const Eigen::Vector2d e_unit = e.normalized();
    for (double ai : {points_[i].point.direction_rad, points_[i].other_direction_rad}) {
      for (double aj : {points_[j].point.direction_rad, points_[j].other_direction_rad}) {
        if (std::abs(AngleDiff(ai, aj)) > f_.o.max_direction_difference_rad) continue;
        if (ShortArmUsed(i, ai) || ShortArmUsed(j, aj)) continue;
        if (!EntranceArmOk(i, ai, e_unit) || !EntranceArmOk(j, aj, -e_unit)) continue;
        const Eigen::Vector2d di(std::cos(ai), std::sin(ai)), dj(std::cos(aj), std::sin(aj));
        const Eigen::Vector2d mean = (di + dj).normalized();
        if (std::abs(Cross(e.normalized(), mean)) < f_.min_sin) continue;
        *dir_i = di;
        *dir_j = dj;
        return true;
      }
    }
    return false;
  }

  // A third marking point on the entrance line between i and j: the pair
  // spans two slots.
  bool ThirdPointOn(size_t i, size_t j) const {
    for (size_t k = 0; k < points_.size(); ++k) {
      if (k == i || k == j) continue;
      double along = 0.0;
      const double dist = PointDistanceToSegment(points_[k].point.px, points_[i].point.px,
                                                 points_[j].point.px, &along);
      if (dist < f_.o.on_line_tolerance_m * f_.s && along > 0.0 && along < 1.0) return true;
    }
    return false;
  }

  const Frame& f_;
  const std::vector<PaintLine>& lines_;
  const std::vector<Junction>& points_;
};

}  // namespace

SlotDetection SlotDetector::Detect(const cv::Mat& top_view, const cv::Mat& mask) const {
  if (top_view.empty() || top_view.depth() != CV_8U ||
      (top_view.channels() != 1 && top_view.channels() != 3)) {
    throw std::invalid_argument("slot detector: expected an 8-bit grey or BGR image");
  }
  if (!mask.empty() && (mask.size() != top_view.size() || mask.type() != CV_8UC1)) {
    throw std::invalid_argument("slot detector: the mask must be 8-bit and of the image's size");
  }
  Frame f(options_);
  PrepareImage(top_view, mask, &f);
  FindPaint(&f);
  const std::vector<PaintLine> lines = FindLines(f);
  const std::vector<Junction> points = SuppressNonMaxima(f, FindJunctions(f, lines));

  SlotDetection result;
  for (const PaintLine& line : lines) {
    result.lines.push_back(
        {line.point + line.t0 * line.dir, line.point + line.t1 * line.dir, line.width_px});
  }
  for (const Junction& junction : points) result.marking_points.push_back(junction.point);
  const EntrancePairing pairing(f, lines, points);
  for (size_t i = 0; i < points.size(); ++i) {
    for (size_t j = i + 1; j < points.size(); ++j) {
      if (std::optional<DetectedSlot> slot = pairing.SlotOf(i, j)) result.slots.push_back(*slot);
    }
  }
  return result;
}

}  // namespace parkslam::perception
