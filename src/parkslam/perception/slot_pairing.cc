#include "parkslam/perception/slot_pairing.h"

#include <algorithm>
#include <cmath>

#include "parkslam/common/angles.h"
#include "parkslam/common/cross.h"
#include "parkslam/common/field_checker.h"

namespace parkslam::perception {
namespace {

// Distance from p to the segment a-b, and where along it (0 at a, 1 at b)
// its foot lies.
double DistanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                         const Eigen::Vector2d& b, double* along) {
  const Eigen::Vector2d ab = b - a;
  *along = (p - a).dot(ab) / ab.squaredNorm();
  return std::abs(Cross(ab.normalized(), p - a));
}

bool InImage(const Eigen::Vector2d& px, const cv::Size& size) {
  return px.x() >= -0.5 && px.y() >= -0.5 && px.x() <= size.width - 0.5 &&
         px.y() <= size.height - 0.5;
}

}  // namespace

bool SlotPairingOptions::IsValid(std::string* error) const {
  FieldChecker c(error);
  c.Positive(pixels_per_m, "pixels_per_m");
  c.Positive(min_entrance_m, "min_entrance_m");
  c.Require(max_entrance_m > min_entrance_m, "max_entrance_m",
            "must be greater than min_entrance_m");
  c.Between(parallel_min_entrance_m, 0.0, 100.0, "parallel_min_entrance_m", "m");
  c.Positive(standard_depth_m, "standard_depth_m");
  c.Positive(parallel_depth_m, "parallel_depth_m");
  c.InRange(parallel_min_depth_in_view_m, 0.0, 10.0, "parallel_min_depth_in_view_m", "m");
  c.InRange(border_width_check_m, 0.0, 10.0, "border_width_check_m", "m");
  c.PositiveAtMost(border_width_share, 1.0, "border_width_share", "");
  c.Between(max_direction_difference_rad, 0.0, M_PI, "max_direction_difference_rad", "rad");
  c.NonNegative(on_line_tolerance_m, "on_line_tolerance_m");
  c.Require(max_vehicle_depth_in_row_m >= 0.0 && max_vehicle_depth_in_row_m <= 100.0,
            "max_vehicle_depth_in_row_m", "must be in [0, 100] m");
  c.Require(min_junction_angle_rad >= 0.0 && min_junction_angle_rad < M_PI / 2,
            "min_junction_angle_rad", "must be in [0, pi/2) rad");
  return c.ok();
}

std::vector<DetectedSlot> PairMarkingPoints(const std::vector<MarkingPoint>& points,
                                            const cv::Size& image_size,
                                            const SlotPairingOptions& o) {
  const double s = o.pixels_per_m;
  const double min_sin = std::sin(o.min_junction_angle_rad);
  const Eigen::Vector2d centre_px((image_size.width - 1) / 2.0, (image_size.height - 1) / 2.0);
  std::vector<DetectedSlot> slots;
  for (size_t i = 0; i < points.size(); ++i) {
    for (size_t j = i + 1; j < points.size(); ++j) {
      const MarkingPoint& a = points[i];
      const MarkingPoint& b = points[j];
      const Eigen::Vector2d e = b.px - a.px;
      const double length_m = e.norm() / s;
      if (length_m < o.min_entrance_m || length_m > o.max_entrance_m) continue;
      if (std::abs(AngleDiff(a.direction_rad, b.direction_rad)) > o.max_direction_difference_rad) {
        continue;
      }
      const Eigen::Vector2d da(std::cos(a.direction_rad), std::sin(a.direction_rad));
      const Eigen::Vector2d db(std::cos(b.direction_rad), std::sin(b.direction_rad));
      const Eigen::Vector2d depth_dir = (da + db).normalized();
      // The separating lines leave the entrance line, not run along it.
      if (std::abs(Cross(e.normalized(), depth_dir)) < min_sin) continue;
      if (!SlotOpensAsAllowed(a.px, b.px, depth_dir, centre_px, s,
                              length_m >= o.parallel_min_entrance_m,
                              o.require_entrance_facing_vehicle, o.max_vehicle_depth_in_row_m)) {
        continue;
      }
      bool third_point = false;
      for (size_t k = 0; k < points.size() && !third_point; ++k) {
        if (k == i || k == j) continue;
        double along = 0.0;
        const double d = DistanceToSegment(points[k].px, a.px, b.px, &along);
        third_point = d < o.on_line_tolerance_m * s && along > 0.0 && along < 1.0;
      }
      if (third_point) continue;
      // Corner order (sensor_data.h): walking from corner 0 to corner 1 the
      // slot lies on the left in the vehicle frame, on the right on screen.
      const bool i_first = Cross(e, depth_dir) < 0.0;
      const size_t first = i_first ? i : j, second = i_first ? j : i;
      const double depth_m =
          length_m >= o.parallel_min_entrance_m ? o.parallel_depth_m : o.standard_depth_m;
      DetectedSlot slot;
      slot.corners_px[0] = points[first].px;
      slot.corners_px[1] = points[second].px;
      slot.corners_px[2] = points[second].px + depth_m * s * depth_dir;
      slot.corners_px[3] = points[first].px + depth_m * s * depth_dir;
      slot.depth_dir_px = depth_dir;
      slot.marking_points = {static_cast<int>(first), static_cast<int>(second)};
      slot.confidence = std::sqrt(a.score * b.score);
      slots.push_back(slot);
    }
  }
  if (!o.drop_points_inside_slots) return slots;
  // A point inside a slot (past the entrance line, short of the far end)
  // contradicts it: the weaker side goes. A point weaker than both of the
  // slot's is dropped with every slot it makes.
  std::vector<bool> dropped(points.size(), false);
  for (const DetectedSlot& slot : slots) {
    const Eigen::Vector2d a = slot.corners_px[0], e = slot.corners_px[1] - a;
    const double depth_px = (slot.corners_px[3] - a).dot(slot.depth_dir_px);
    const double weakest =
        std::min(points[slot.marking_points[0]].score, points[slot.marking_points[1]].score);
    for (size_t k = 0; k < points.size(); ++k) {
      const double along = (points[k].px - a).dot(e) / e.squaredNorm();
      const double depth = (points[k].px - a).dot(slot.depth_dir_px);
      if (along > 0.0 && along < 1.0 && depth > o.on_line_tolerance_m * s && depth < depth_px &&
          points[k].score < weakest) {
        dropped[k] = true;
      }
    }
  }
  std::vector<DetectedSlot> kept;
  for (const DetectedSlot& slot : slots) {
    if (!dropped[slot.marking_points[0]] && !dropped[slot.marking_points[1]]) kept.push_back(slot);
  }
  return kept;
}

void DropParallelSlotsLeavingTheView(const cv::Size& image_size, const SlotPairingOptions& o,
                                     std::vector<DetectedSlot>* slots) {
  if (o.parallel_min_depth_in_view_m <= 0.0) return;
  const double s = o.pixels_per_m;
  const double reach_px = o.parallel_min_depth_in_view_m * s;
  std::erase_if(*slots, [&](const DetectedSlot& slot) {
    const double length_m = (slot.corners_px[1] - slot.corners_px[0]).norm() / s;
    return length_m >= o.parallel_min_entrance_m &&
           (!InImage(slot.corners_px[0] + reach_px * slot.depth_dir_px, image_size) ||
            !InImage(slot.corners_px[1] + reach_px * slot.depth_dir_px, image_size));
  });
}

void DropOddSlotsAtTheBorder(const cv::Size& image_size, const SlotPairingOptions& o,
                             std::vector<DetectedSlot>* slots) {
  if (o.border_width_check_m <= 0.0) return;
  const double border_px = o.border_width_check_m * o.pixels_per_m;
  const auto to_border = [&](const Eigen::Vector2d& p) {
    return std::min({p.x(), p.y(), image_size.width - 1 - p.x(), image_size.height - 1 - p.y()});
  };
  const auto width = [](const DetectedSlot& s) {
    return (s.corners_px[1] - s.corners_px[0]).norm();
  };
  std::vector<bool> odd(slots->size(), false);
  for (size_t i = 0; i < slots->size(); ++i) {
    const DetectedSlot& slot = (*slots)[i];
    for (int e = 0; e < 2 && !odd[i]; ++e) {
      if (to_border(slot.corners_px[e]) >= border_px) continue;
      const int other = slot.marking_points[1 - e];
      for (size_t j = 0; j < slots->size() && !odd[i]; ++j) {
        const DetectedSlot& n = (*slots)[j];
        if (j == i || (n.marking_points[0] != other && n.marking_points[1] != other)) continue;
        odd[i] = std::abs(width(slot) - width(n)) > o.border_width_share * width(n);
      }
    }
  }
  std::vector<DetectedSlot> kept;
  for (size_t i = 0; i < slots->size(); ++i) {
    if (!odd[i]) kept.push_back((*slots)[i]);
  }
  *slots = std::move(kept);
}

}  // namespace parkslam::perception
