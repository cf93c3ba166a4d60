#include "parkslam/perception/learned_slot_detector.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>

#include "parkslam/common/angles.h"
#include "parkslam/common/field_checker.h"

namespace parkslam::perception {
namespace {

constexpr int kStride = 16;  // the network's output stride
constexpr int kOutputs = 6;  // confidence, offset x, offset y, cos, sin, T

}  // namespace

bool LearnedSlotDetectorOptions::IsValid(std::string* error) const {
  FieldChecker c(error);
  c.Require(!model_path.empty(), "model_path", "is empty");
  c.Require(input_size_px >= kStride && input_size_px % kStride == 0, "input_size_px",
            "must be a positive multiple of 16");
  c.Between(min_confidence, 0.0, 1.0, "min_confidence", "");
  c.Require(min_partner_confidence >= 0.0 && min_partner_confidence <= min_confidence,
            "min_partner_confidence", "must be in [0, min_confidence]");
  c.Require(weak_point_min_confidence >= 0.0 && weak_point_min_confidence <= min_confidence,
            "weak_point_min_confidence", "must be in [0, min_confidence]");
  c.PositiveAtMost(weak_point_max_angle_rad, 1.5707963267948966, "weak_point_max_angle_rad", "rad");
  c.Require(weak_point_min_painted_share >= 0.0 && weak_point_min_painted_share <= 1.0,
            "weak_point_min_painted_share", "must be in [0, 1]");
  c.Require(flips == 1 || flips == 2 || flips == 4, "flips", "must be 1, 2 or 4");
  c.NonNegative(nms_radius_px, "nms_radius_px");
  c.InRange(max_point_depth_towards_car_m, 0.0, 100.0, "max_point_depth_towards_car_m", "m");
  c.Positive(extend_tolerance_m, "extend_tolerance_m");
  c.InRange(border_margin_m, 0.0, 2.0, "border_margin_m", "m");
  c.Positive(classical_match_px, "classical_match_px");
  c.Positive(classical_match_rad, "classical_match_rad");
  c.Part(pairing, "pairing");
  c.Part(paint_check, "paint_check");
  c.Part(classical_options, "classical_options");
  return c.ok();
}

LearnedSlotDetector::LearnedSlotDetector(const LearnedSlotDetectorOptions& options)
    : options_(options) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument("LearnedSlotDetectorOptions: " + error);
  const int n = options.input_size_px, g = n / kStride;
  paint_check_ = options.paint_check;
  paint_check_.pixels_per_m = options.pairing.pixels_per_m;
  if (options.classical != ClassicalCheck::kNone) {
    SlotDetectorOptions classical = options.classical_options;
    classical.pixels_per_m = options.pairing.pixels_per_m;
    classical_ = std::make_unique<SlotDetector>(classical);
  }
  network_ = std::make_unique<OnnxNetwork>(options.model_path, std::vector<int>{1, 3, n, n},
                                           std::vector<int>{1, kOutputs, g, g});
}

cv::Mat LearnedSlotDetector::Cells(const cv::Mat& top_view) const {
  if (top_view.empty() || top_view.depth() != CV_8U ||
      (top_view.channels() != 1 && top_view.channels() != 3)) {
    throw std::invalid_argument("LearnedSlotDetector: expected an 8-bit grey or BGR top view");
  }
  const int n = options_.input_size_px;
  cv::Mat resized;
  // INTER_AREA, as the training script resizes (scripts/learned/); a grey
  // view becomes BGR after resizing, on a ninth of the pixels.
  cv::resize(top_view, resized, cv::Size(n, n), 0, 0, cv::INTER_AREA);
  if (resized.channels() == 1) cv::cvtColor(resized, resized, cv::COLOR_GRAY2BGR);
  const int g = n / kStride;
  cv::Mat sum =
      network_->Forward(cv::dnn::blobFromImage(resized)).reshape(1, {kOutputs, g, g}).clone();
  if (options_.flips == 1) return sum;
  // Mirrored views: flip code 1 mirrors x, 0 mirrors y, -1 both. A cell
  // (cx, cy) of the mirrored view is (g - 1 - cx, cy) of the view (x
  // mirrored), its offset 1 - offset and its direction's cos negated; the
  // same for y with sin.
  const std::vector<int> codes =
      options_.flips == 2 ? std::vector<int>{1} : std::vector<int>{1, 0, -1};
  for (const int code : codes) {
    cv::Mat flipped;
    cv::flip(resized, flipped, code);
    const cv::Mat out =
        network_->Forward(cv::dnn::blobFromImage(flipped)).reshape(1, {kOutputs, g, g});
    const bool fx = code != 0, fy = code != 1;
    for (int cy = 0; cy < g; ++cy) {
      for (int cx = 0; cx < g; ++cx) {
        const int sx = fx ? g - 1 - cx : cx, sy = fy ? g - 1 - cy : cy;
        const auto at = [&](int k) { return out.at<float>(k, sy, sx); };
        sum.at<float>(0, cy, cx) += at(0);
        sum.at<float>(1, cy, cx) += fx ? 1.0f - at(1) : at(1);
        sum.at<float>(2, cy, cx) += fy ? 1.0f - at(2) : at(2);
        sum.at<float>(3, cy, cx) += fx ? -at(3) : at(3);
        sum.at<float>(4, cy, cx) += fy ? -at(4) : at(4);
        sum.at<float>(5, cy, cx) += at(5);
      }
    }
  }
  // Means; the direction's (cos, sin) only by its angle, so its length
  // does not matter.
  sum *= 1.0 / options_.flips;
  return sum;
}

void LearnedSlotDetector::CheckOnPaint(const cv::Mat& grey, const cv::Mat& mask,
                                       SlotDetection* detection) const {
  // Slots with no separating line across them; the lines of the others
  // become marking points (T: the entrance line goes on past a missed
  // point in most lots).
  const auto keep_uncrossed = [&](std::vector<MarkingPoint>* recovered) {
    std::vector<DetectedSlot> kept;
    for (const DetectedSlot& slot : detection->slots) {
      const SlotPaint paint = MeasureSlotPaint(grey, mask, slot, paint_check_);
      if (paint.lines_inside.empty()) kept.push_back(slot);
      if (recovered == nullptr) continue;
      for (const Eigen::Vector2d& at : paint.lines_inside) {
        MarkingPoint p;
        p.px = at;
        p.direction_rad = std::atan2(slot.depth_dir_px.y(), slot.depth_dir_px.x());
        p.shape = MarkingShape::kT;
        p.score = slot.confidence;
        recovered->push_back(p);
      }
    }
    detection->slots = std::move(kept);
  };
  const double r2 = options_.nms_radius_px * options_.nms_radius_px;
  std::vector<MarkingPoint>& points = detection->marking_points;
  // New points (two candidates across one missed point find its line
  // twice) join the others, which are paired and checked again.
  const auto pair_again_with = [&](const std::vector<MarkingPoint>& more) {
    size_t added = 0;
    for (const MarkingPoint& p : more) {
      if (std::none_of(points.begin(), points.end(),
                       [&](const MarkingPoint& q) { return (p.px - q.px).squaredNorm() < r2; })) {
        points.push_back(p);
        ++added;
      }
    }
    if (added == 0) return;
    detection->slots = PairMarkingPoints(points, grey.size(), options_.pairing);
    keep_uncrossed(nullptr);
  };
  std::vector<MarkingPoint> recovered;
  keep_uncrossed(options_.recover_points ? &recovered : nullptr);
  pair_again_with(recovered);
  if (options_.extend_rows) pair_again_with(MissedRowCorners(grey, mask, *detection));
}

std::vector<MarkingPoint> LearnedSlotDetector::MissedRowCorners(
    const cv::Mat& grey, const cv::Mat& mask, const SlotDetection& detection) const {
  const double s = options_.pairing.pixels_per_m;
  std::vector<Eigen::Vector2d> known;
  for (const MarkingPoint& p : detection.marking_points) known.push_back(p.px);
  std::vector<MarkingPoint> found;
  for (const RowCorner& corner : FindRowCorners(grey, mask, detection.slots, known,
                                                options_.pairing.parallel_min_entrance_m * s,
                                                options_.extend_tolerance_m * s, paint_check_)) {
    const DetectedSlot& slot = detection.slots[static_cast<size_t>(corner.slot)];
    MarkingPoint p;
    p.px = corner.px;
    p.direction_rad = std::atan2(slot.depth_dir_px.y(), slot.depth_dir_px.x());
    p.shape = MarkingShape::kT;
    p.score = slot.confidence;
    found.push_back(p);
  }
  return found;
}

SlotDetection LearnedSlotDetector::Detect(const cv::Mat& top_view, const cv::Mat& mask) const {
  const cv::Mat cells = Cells(top_view);
  const int g = cells.size[1];
  // A cell's place (cx + offset) / g spans the image from edge to edge;
  // 0-based pixel centres sit half a pixel in.
  const double scale_x = static_cast<double>(top_view.cols) / g;
  const double scale_y = static_cast<double>(top_view.rows) / g;
  const double border_px = options_.border_margin_m * options_.pairing.pixels_per_m;
  const Eigen::Vector2d centre_px((top_view.cols - 1) / 2.0, (top_view.rows - 1) / 2.0);
  const double max_towards_px =
      options_.max_point_depth_towards_car_m * options_.pairing.pixels_per_m;
  std::vector<MarkingPoint> found;
  for (int cy = 0; cy < g; ++cy) {
    for (int cx = 0; cx < g; ++cx) {
      const auto at = [&](int k) { return static_cast<double>(cells.at<float>(k, cy, cx)); };
      const double lowest = std::min(
          {options_.min_confidence,
           options_.min_partner_confidence > 0.0 ? options_.min_partner_confidence : 1.0,
           options_.weak_point_min_confidence > 0.0 ? options_.weak_point_min_confidence : 1.0});
      if (at(0) < lowest) continue;
      MarkingPoint p;
      p.px = Eigen::Vector2d((cx + at(1)) * scale_x - 0.5, (cy + at(2)) * scale_y - 0.5);
      p.direction_rad = std::atan2(at(4), at(3));
      p.shape = at(5) >= 0.5 ? MarkingShape::kT : MarkingShape::kL;
      p.score = at(0);
      const double towards_car_px = std::cos(p.direction_rad) * (centre_px.x() - p.px.x()) +
                                    std::sin(p.direction_rad) * (centre_px.y() - p.px.y());
      if (options_.max_point_depth_towards_car_m > 0.0 && towards_car_px > max_towards_px) continue;
      if (p.px.x() < border_px || p.px.y() < border_px ||
          p.px.x() > top_view.cols - 1 - border_px || p.px.y() > top_view.rows - 1 - border_px) {
        continue;
      }
      if (!mask.empty()) {
        const int u = std::clamp(static_cast<int>(std::lround(p.px.x())), 0, mask.cols - 1);
        const int v = std::clamp(static_cast<int>(std::lround(p.px.y())), 0, mask.rows - 1);
        if (mask.at<unsigned char>(v, u) == 0) continue;
      }
      found.push_back(p);
    }
  }
  std::sort(found.begin(), found.end(),
            [](const MarkingPoint& a, const MarkingPoint& b) { return a.score > b.score; });
  SlotDetection result;
  const double r2 = options_.nms_radius_px * options_.nms_radius_px;
  for (const MarkingPoint& p : found) {
    const bool near_kept =
        std::any_of(result.marking_points.begin(), result.marking_points.end(),
                    [&](const MarkingPoint& q) { return (p.px - q.px).squaredNorm() < r2; });
    if (!near_kept) result.marking_points.push_back(p);
  }
  cv::Mat grey = top_view;
  if (grey.channels() == 3) cv::cvtColor(top_view, grey, cv::COLOR_BGR2GRAY);
  if (options_.weak_point_min_confidence > 0.0 || options_.strong_points_need_paint) {
    // Points below the threshold stay where the paint shows their
    // junction; with strong_points_need_paint, points above it go where
    // the paint is in view and shows none.
    std::vector<MarkingPoint> kept;
    for (const MarkingPoint& p : result.marking_points) {
      const bool strong = p.score >= options_.min_confidence;
      const bool weak =
          options_.weak_point_min_confidence > 0.0 && p.score >= options_.weak_point_min_confidence;
      const bool partner =
          options_.min_partner_confidence > 0.0 && p.score >= options_.min_partner_confidence;
      if (!strong && !weak) {
        if (partner) kept.push_back(p);  // left to the partner rule below
        continue;
      }
      if (strong && !options_.strong_points_need_paint) {
        kept.push_back(p);
        continue;
      }
      const PointPaint paint =
          MeasurePointPaint(grey, mask, p.px, p.direction_rad, options_.weak_point_max_angle_rad,
                            options_.weak_point_min_painted_share, paint_check_);
      const bool junction = paint.separating && paint.entrance;
      if (junction || (strong && !paint.in_view)) kept.push_back(p);
    }
    result.marking_points = std::move(kept);
  }
  if (options_.min_partner_confidence > 0.0) {
    // Weak points stay only as partners of strong ones in a slot.
    const std::vector<DetectedSlot> candidates =
        PairMarkingPoints(result.marking_points, top_view.size(), options_.pairing);
    std::vector<bool> keep(result.marking_points.size(), false);
    for (size_t i = 0; i < keep.size(); ++i)
      keep[i] = result.marking_points[i].score >= options_.min_confidence;
    for (const DetectedSlot& slot : candidates) {
      const int a = slot.marking_points[0], b = slot.marking_points[1];
      const bool strong_a = result.marking_points[a].score >= options_.min_confidence;
      const bool strong_b = result.marking_points[b].score >= options_.min_confidence;
      if (strong_a || strong_b) keep[a] = keep[b] = true;
    }
    std::vector<MarkingPoint> kept;
    for (size_t i = 0; i < keep.size(); ++i)
      if (keep[i]) kept.push_back(result.marking_points[i]);
    result.marking_points = std::move(kept);
  }
  if (classical_ != nullptr) {
    const std::vector<MarkingPoint> lines_points =
        classical_->Detect(top_view, mask).marking_points;
    std::vector<MarkingPoint> checked;
    for (MarkingPoint p : result.marking_points) {
      const MarkingPoint* best = nullptr;
      for (const MarkingPoint& q : lines_points) {
        const double d = (q.px - p.px).norm();
        if (d <= options_.classical_match_px &&
            std::abs(AngleDiff(q.direction_rad, p.direction_rad)) <= options_.classical_match_rad &&
            (best == nullptr || d < (best->px - p.px).norm())) {
          best = &q;
        }
      }
      if (best != nullptr) {
        p.px = best->px;
        p.direction_rad = best->direction_rad;
      }
      if (best != nullptr || options_.classical == ClassicalCheck::kRefine) checked.push_back(p);
    }
    result.marking_points = std::move(checked);
  }
  result.slots = PairMarkingPoints(result.marking_points, top_view.size(), options_.pairing);
  if (options_.check_paint || options_.refine_on_paint) {
    if (options_.check_paint) CheckOnPaint(grey, mask, &result);
    if (options_.refine_on_paint) {
      for (DetectedSlot& slot : result.slots) {
        RefineSlotCorners(grey, mask, paint_check_, &slot);
        for (int e = 0; e < 2; ++e) {
          MarkingPoint& p = result.marking_points[slot.marking_points[e]];
          p.px = slot.corners_px[e];
          p.direction_rad = std::atan2(slot.depth_dir_px.y(), slot.depth_dir_px.x());
        }
      }
    }
  }
  // Last, so that the paint check may still recover a point across one.
  DropParallelSlotsLeavingTheView(top_view.size(), options_.pairing, &result.slots);
  DropOddSlotsAtTheBorder(top_view.size(), options_.pairing, &result.slots);
  return result;
}

}  // namespace parkslam::perception
