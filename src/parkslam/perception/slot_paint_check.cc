#include "parkslam/perception/slot_paint_check.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "parkslam/common/field_checker.h"

namespace parkslam::perception {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Bilinear sample of a CV_8UC1 image at p; NaN outside it, on masked
// pixels and on black (unseen) ones.
double SampleInView(const cv::Mat& grey, const cv::Mat& mask, const Eigen::Vector2d& p) {
  const double x = p.x(), y = p.y();
  if (!(x >= 0.0 && y >= 0.0 && x <= grey.cols - 1.0 && y <= grey.rows - 1.0)) return kNaN;
  const int u = static_cast<int>(std::lround(x)), v = static_cast<int>(std::lround(y));
  if (grey.at<unsigned char>(v, u) == 0) return kNaN;
  if (!mask.empty() && mask.at<unsigned char>(v, u) == 0) return kNaN;
  const int x0 = std::min(static_cast<int>(x), grey.cols - 2);
  const int y0 = std::min(static_cast<int>(y), grey.rows - 2);
  const double fx = x - x0, fy = y - y0;
  const auto at = [&](int r, int c) { return static_cast<double>(grey.at<unsigned char>(r, c)); };
  return (1.0 - fy) * ((1.0 - fx) * at(y0, x0) + fx * at(y0, x0 + 1)) +
         fy * ((1.0 - fx) * at(y0 + 1, x0) + fx * at(y0 + 1, x0 + 1));
}

// How far a stripe centred at each sample of a (1-px) profile stands above
// both sides: the sample less the brighter of the two samples h + 1 away,
// the best over half widths h in [min_half, max_half]. A stripe wider than
// the widest line (a car's body) has bright sides, a step (a shadow's edge)
// one bright side. NaN where a sample it needs is.
std::vector<double> StripeContrast(const std::vector<double>& profile, int min_half, int max_half) {
  const int n = static_cast<int>(profile.size());
  std::vector<double> contrast(n, kNaN);
  for (int i = max_half + 1; i + max_half + 1 < n; ++i) {
    double best = kNaN;
    for (int h = min_half; h <= max_half; ++h) {
      const double c = profile[i] - std::max(profile[i - h - 1], profile[i + h + 1]);
      if (std::isnan(c)) {
        best = kNaN;
        break;
      }
      best = std::isnan(best) ? c : std::max(best, c);
    }
    contrast[i] = best;
  }
  return contrast;
}

// The largest finite value in [begin, end); NaN when there is none.
double MaxIn(const std::vector<double>& values, int begin, int end) {
  double best = kNaN;
  for (int i = std::max(begin, 0); i < std::min(end, static_cast<int>(values.size())); ++i) {
    if (std::isfinite(values[i]) && !(values[i] <= best)) best = values[i];
  }
  return best;
}

// The least-squares line y = mean_y + slope (x - mean_x) through points
// (x[k], y[k]); slope 0 when the x are all equal.
struct StraightFit {
  double mean_x = 0.0, mean_y = 0.0, slope = 0.0;
};
StraightFit FitStraight(const std::vector<double>& x, const std::vector<double>& y) {
  StraightFit fit;
  for (size_t k = 0; k < x.size(); ++k) {
    fit.mean_x += x[k] / x.size();
    fit.mean_y += y[k] / x.size();
  }
  double sxy = 0.0, sxx = 0.0;
  for (size_t k = 0; k < x.size(); ++k) {
    sxy += (x[k] - fit.mean_x) * (y[k] - fit.mean_y);
    sxx += (x[k] - fit.mean_x) * (x[k] - fit.mean_x);
  }
  fit.slope = sxx > 0.0 ? sxy / sxx : 0.0;
  return fit;
}

// A painted line near `origin`, roughly along unit `dir`: cross-sections
// along its normal at t in [t_begin, t_end] px along `dir`, each
// +-half_window px wide, whose response above their median peaks by at
// least min_contrast; the centroid of each section's response above a
// quarter of its peak is a centre. Fits the line through the centres
// (least squares of the offset against t) and returns false when fewer
// than min_sections show paint. in_view_count, when given, counts the
// sections wholly in view, painted or not, and painted_count those with
// paint.
bool FitLineNear(const cv::Mat& grey, const cv::Mat& mask, const Eigen::Vector2d& origin,
                 const Eigen::Vector2d& dir, double t_begin, double t_end, double half_window,
                 double min_contrast, int min_sections, Eigen::Vector2d* point,
                 Eigen::Vector2d* direction, int* in_view_count = nullptr,
                 int* painted_count = nullptr) {
  const Eigen::Vector2d normal(-dir.y(), dir.x());
  const int half = static_cast<int>(std::ceil(half_window));
  std::vector<double> ts, offsets, profile(2 * half + 1), sorted;
  for (double t = t_begin; t <= t_end; t += 1.0) {
    const Eigen::Vector2d base = origin + t * dir;
    bool in_view = true;
    for (int i = -half; i <= half && in_view; ++i) {
      profile[i + half] = SampleInView(grey, mask, base + static_cast<double>(i) * normal);
      in_view = !std::isnan(profile[i + half]);
    }
    if (!in_view) continue;
    if (in_view_count != nullptr) ++*in_view_count;
    sorted = profile;
    std::nth_element(sorted.begin(), sorted.begin() + half, sorted.end());
    const double floor = sorted[half];
    const double peak = *std::max_element(profile.begin(), profile.end()) - floor;
    if (peak < min_contrast) continue;
    double sum = 0.0, moment = 0.0;
    for (int i = -half; i <= half; ++i) {
      const double w = profile[i + half] - floor - 0.25 * peak;
      if (w <= 0.0) continue;
      sum += w;
      moment += w * i;
    }
    ts.push_back(t);
    offsets.push_back(moment / sum);
  }
  if (painted_count != nullptr) *painted_count = static_cast<int>(ts.size());
  if (static_cast<int>(ts.size()) < min_sections) return false;
  const StraightFit fit = FitStraight(ts, offsets);
  *point = origin + fit.mean_x * dir + fit.mean_y * normal;
  *direction = (dir + fit.slope * normal).normalized();
  return true;
}

}  // namespace

bool SlotPaintCheckOptions::IsValid(std::string* error) const {
  FieldChecker c(error);
  c.Positive(pixels_per_m, "pixels_per_m");
  c.NonNegative(first_depth_m, "first_depth_m");
  c.Positive(depth_step_m, "depth_step_m");
  c.InRange(depth_count, 2, 20, "depth_count", "");
  c.Require(min_depths_in_view >= 2 && min_depths_in_view <= depth_count, "min_depths_in_view",
            "must be in [2, depth_count]");
  c.Require(min_share_in_view > 0.0 && min_share_in_view <= 1.0, "min_share_in_view",
            "must be in (0, 1]");
  c.NonNegative(end_margin_m, "end_margin_m");
  c.Positive(min_line_width_m, "min_line_width_m");
  c.Require(max_line_width_m >= min_line_width_m && max_line_width_m <= 2.0, "max_line_width_m",
            "must be in [min_line_width_m, 2] m");
  c.NonNegative(min_contrast_grey, "min_contrast_grey");
  c.InRange(own_line_share, 0.0, 1.0, "own_line_share", "");
  c.Positive(max_drift_m, "max_drift_m");
  c.NonNegative(refine_begin_m, "refine_begin_m");
  c.Require(refine_end_m > refine_begin_m && refine_end_m <= 5.0, "refine_end_m",
            "must be in (refine_begin_m, 5] m");
  c.Require(refine_separating_end_m > refine_begin_m && refine_separating_end_m <= 5.0,
            "refine_separating_end_m", "must be in (refine_begin_m, 5] m");
  c.PositiveAtMost(refine_half_window_m, 2.0, "refine_half_window_m", "m");
  c.InRange(refine_min_sections, 2, 1000, "refine_min_sections", "");
  return c.ok();
}

SlotPaint MeasureSlotPaint(const cv::Mat& grey, const cv::Mat& mask, const DetectedSlot& slot,
                           const SlotPaintCheckOptions& o) {
  SlotPaint result;
  const double s = o.pixels_per_m;
  const Eigen::Vector2d origin = slot.corners_px[0];
  const Eigen::Vector2d entrance = slot.corners_px[1] - origin;
  const double length_px = entrance.norm();
  if (!(length_px > 0.0)) return result;
  const Eigen::Vector2d along = entrance / length_px;
  const Eigen::Vector2d depth = slot.depth_dir_px.normalized();
  const int min_half = std::max(1, static_cast<int>(std::floor(o.min_line_width_m * s / 2.0)));
  const int max_half =
      std::max(min_half, static_cast<int>(std::ceil(o.max_line_width_m * s / 2.0)));
  // Profiles from a line's width before corner 0 to a line's width past
  // corner 1, so that the slot's own lines are measured too.
  const int pad = 2 * max_half + 2;
  const int n = static_cast<int>(std::floor(length_px)) + 2 * pad + 1;
  const auto index_of = [&](double u_px) { return static_cast<int>(std::lround(u_px)) + pad; };
  const int inside_begin = index_of(o.end_margin_m * s);
  const int inside_end = index_of(length_px - o.end_margin_m * s);
  if (inside_end <= inside_begin) return result;

  // Contrast profiles, one per depth, and the contrast of the slot's own
  // separating lines.
  std::vector<std::vector<double>> contrasts;
  std::vector<double> depths_m;  // of the cross-sections in view
  std::vector<double> own;
  for (int k = 0; k < o.depth_count; ++k) {
    const Eigen::Vector2d base = origin + (o.first_depth_m + k * o.depth_step_m) * s * depth;
    std::vector<double> profile(n);
    for (int i = 0; i < n; ++i) {
      profile[i] = SampleInView(grey, mask, base + static_cast<double>(i - pad) * along);
    }
    // Smoothed over three samples against the floor's grain.
    std::vector<double> smooth(profile);
    for (int i = 1; i + 1 < n; ++i)
      smooth[i] = (profile[i - 1] + profile[i] + profile[i + 1]) / 3.0;
    std::vector<double> contrast = StripeContrast(smooth, min_half, max_half);
    // A cross-section mostly out of view cannot show a line for certain.
    const auto seen = std::count_if(contrast.begin() + inside_begin, contrast.begin() + inside_end,
                                    [](double c) { return !std::isnan(c); });
    if (seen < o.min_share_in_view * (inside_end - inside_begin)) continue;
    depths_m.push_back(o.first_depth_m + k * o.depth_step_m);
    for (const int end : {index_of(0.0), index_of(length_px)}) {
      const double c = MaxIn(contrast, end - max_half - 1, end + max_half + 2);
      if (std::isfinite(c)) own.push_back(c);
    }
    contrasts.push_back(std::move(contrast));
  }
  if (static_cast<int>(contrasts.size()) < o.min_depths_in_view) return result;
  double threshold = o.min_contrast_grey;
  if (!own.empty()) {
    std::nth_element(own.begin(), own.begin() + own.size() / 2, own.end());
    threshold = std::max(threshold, o.own_line_share * own[own.size() / 2]);
  }

  // Stripes: local maxima of the contrast above the threshold.
  std::vector<std::vector<int>> stripes(contrasts.size());
  for (size_t k = 0; k < contrasts.size(); ++k) {
    const std::vector<double>& c = contrasts[k];
    for (int i = inside_begin; i < inside_end; ++i) {
      if (c[i] >= threshold && !(c[i - 1] > c[i]) && !(c[i + 1] >= c[i])) stripes[k].push_back(i);
    }
  }
  // A separating line: a stripe in every cross-section, each within
  // max_drift of the one before; where it meets the entrance, from the
  // least-squares line through them (u against depth).
  const double max_drift_px = o.max_drift_m * s;
  std::vector<std::vector<double>> at_entrance;  // per line, along the entrance (px)
  for (const int first : stripes[0]) {
    std::vector<double> u{static_cast<double>(first - pad)};
    for (size_t k = 1; k < stripes.size(); ++k) {
      double best = kNaN;
      for (const int i : stripes[k]) {
        const double d = std::abs((i - pad) - u.back());
        if (d <= max_drift_px && !(d >= std::abs(best - u.back()))) best = i - pad;
      }
      if (std::isnan(best)) break;
      u.push_back(best);
    }
    if (u.size() != stripes.size()) continue;
    const StraightFit fit = FitStraight(depths_m, u);
    const double u_at_entrance = fit.mean_y - fit.slope * fit.mean_x;
    // Two maxima of one line's flat top (noise) are one line: their mean.
    if (!at_entrance.empty() && u_at_entrance - at_entrance.back().back() < 2 * max_half) {
      at_entrance.back().push_back(u_at_entrance);
    } else {
      at_entrance.push_back({u_at_entrance});
    }
  }
  for (const std::vector<double>& line : at_entrance) {
    const double u = std::accumulate(line.begin(), line.end(), 0.0) / line.size();
    result.lines_inside.push_back(origin + u * along);
  }
  return result;
}

std::vector<RowCorner> FindRowCorners(const cv::Mat& grey, const cv::Mat& mask,
                                      const std::vector<DetectedSlot>& slots,
                                      const std::vector<Eigen::Vector2d>& known_px,
                                      double max_width_px, double tolerance_px,
                                      const SlotPaintCheckOptions& options) {
  std::vector<RowCorner> found;
  for (size_t k = 0; k < slots.size(); ++k) {
    const DetectedSlot& slot = slots[k];
    const Eigen::Vector2d width = slot.corners_px[1] - slot.corners_px[0];
    if (width.norm() >= max_width_px) continue;
    for (const int end : {0, 1}) {
      const Eigen::Vector2d from = slot.corners_px[end];
      const Eigen::Vector2d step = end == 1 ? width : Eigen::Vector2d(-width);
      const Eigen::Vector2d expected = from + step;
      if (std::any_of(known_px.begin(), known_px.end(), [&](const Eigen::Vector2d& q) {
            return (q - expected).norm() < 0.5 * step.norm();
          })) {
        continue;
      }
      DetectedSlot probe = slot;
      probe.corners_px[0] = from;
      probe.corners_px[1] = expected + step.normalized() * (2.0 * tolerance_px);
      for (const Eigen::Vector2d& at : MeasureSlotPaint(grey, mask, probe, options).lines_inside) {
        if ((at - expected).norm() > tolerance_px || !(at.x() >= 0.0 && at.y() >= 0.0) ||
            at.x() > grey.cols - 1 || at.y() > grey.rows - 1) {
          continue;
        }
        found.push_back({at, static_cast<int>(k)});
        break;
      }
    }
  }
  return found;
}

int RefineSlotCorners(const cv::Mat& grey, const cv::Mat& mask, const SlotPaintCheckOptions& o,
                      DetectedSlot* slot) {
  const double s = o.pixels_per_m;
  const Eigen::Vector2d depth = slot->depth_dir_px.normalized();
  const double depth_px = (slot->corners_px[3] - slot->corners_px[0]).dot(depth);
  const double half_window = o.refine_half_window_m * s;
  Eigen::Vector2d depth_sum = Eigen::Vector2d::Zero();
  int moved = 0;
  for (const int e : {0, 1}) {
    const Eigen::Vector2d corner = slot->corners_px[e];
    const Eigen::Vector2d towards_other = (slot->corners_px[1 - e] - corner).normalized();
    Eigen::Vector2d sep_point, sep_dir, ent_point, ent_dir;
    if (!FitLineNear(grey, mask, corner, depth, o.refine_begin_m * s, o.refine_separating_end_m * s,
                     half_window, o.min_contrast_grey, o.refine_min_sections, &sep_point,
                     &sep_dir) ||
        !FitLineNear(grey, mask, corner, towards_other, o.refine_begin_m * s, o.refine_end_m * s,
                     half_window, o.min_contrast_grey, o.refine_min_sections, &ent_point,
                     &ent_dir)) {
      continue;
    }
    // The crossing of sep_point + a sep_dir and ent_point + b ent_dir.
    const double det = sep_dir.x() * (-ent_dir.y()) - sep_dir.y() * (-ent_dir.x());
    if (std::abs(det) < 0.5) continue;  // lines too close to parallel
    const Eigen::Vector2d r = ent_point - sep_point;
    const double a = (r.x() * (-ent_dir.y()) - r.y() * (-ent_dir.x())) / det;
    const Eigen::Vector2d crossing = sep_point + a * sep_dir;
    // A crossing far from the detected corner is another junction's.
    if ((crossing - corner).norm() > half_window) continue;
    slot->corners_px[e] = crossing;
    depth_sum += sep_dir;
    ++moved;
  }
  // The far corners (guessed at the standard depth) behind the refined
  // entrance, along the measured separating lines: a degree off the
  // network's direction is 9 cm at 5.3 m.
  if (moved > 0) slot->depth_dir_px = depth_sum.normalized();
  slot->corners_px[3] = slot->corners_px[0] + depth_px * slot->depth_dir_px;
  slot->corners_px[2] = slot->corners_px[1] + depth_px * slot->depth_dir_px;
  return moved;
}

PointPaint MeasurePointPaint(const cv::Mat& grey, const cv::Mat& mask, const Eigen::Vector2d& px,
                             double direction_rad, double max_angle_rad, double min_painted_share,
                             const SlotPaintCheckOptions& o) {
  PointPaint result;
  const double s = o.pixels_per_m;
  const double half_window = o.refine_half_window_m * s;
  const double min_cos = std::cos(max_angle_rad);
  // A line from px along unit dir over [begin, end] m: whether it is there,
  // and how many of its cross-sections were in view.
  const auto line_along = [&](const Eigen::Vector2d& dir, double end_m, int* in_view) {
    Eigen::Vector2d point, fitted;
    int painted = 0;
    *in_view = 0;
    return FitLineNear(grey, mask, px, dir, o.refine_begin_m * s, end_m * s, half_window,
                       o.min_contrast_grey, o.refine_min_sections, &point, &fitted, in_view,
                       &painted) &&
           painted >= min_painted_share * *in_view && fitted.dot(dir) >= min_cos;
  };
  const Eigen::Vector2d along(std::cos(direction_rad), std::sin(direction_rad));
  int separating_in_view = 0;
  result.separating = line_along(along, o.refine_separating_end_m, &separating_in_view);
  // The entrance line leaves the junction at a right angle, to one side
  // (an L) or to both (a T).
  int entrance_in_view = 0;
  for (const double side : {1.0, -1.0}) {
    int in_view = 0;
    if (line_along(side * Eigen::Vector2d(-along.y(), along.x()), o.refine_end_m, &in_view)) {
      result.entrance = true;
    }
    entrance_in_view = std::max(entrance_in_view, in_view);
  }
  result.in_view =
      separating_in_view >= o.refine_min_sections && entrance_in_view >= o.refine_min_sections;
  return result;
}

}  // namespace parkslam::perception
