#include "parkslam/harness/perception_eval.h"

#include <cmath>

#include "parkslam/render/ground_raster.h"

namespace parkslam::harness {
namespace {

bool InView(const Eigen::Vector2d& px, const cv::Mat& mask, double margin_px, double gap_px) {
  if (px.x() < margin_px || px.y() < margin_px || px.x() > mask.cols - 1 - margin_px ||
      px.y() > mask.rows - 1 - margin_px) {
    return false;
  }
  const int r = static_cast<int>(std::ceil(gap_px));
  const int cx = static_cast<int>(std::lround(px.x())), cy = static_cast<int>(std::lround(px.y()));
  for (int y = std::max(0, cy - r); y <= std::min(mask.rows - 1, cy + r); ++y) {
    for (int x = std::max(0, cx - r); x <= std::min(mask.cols - 1, cx + r); ++x) {
      if (mask.at<std::uint8_t>(y, x) == 0) return false;
    }
  }
  return true;
}

// Indices of the detections matching a true item or no ignored one.
template <typename T, typename Match>
std::vector<int> Scored(const std::vector<T>& detected, const std::vector<T>& truth,
                        const std::vector<T>& ignored, Match match) {
  std::vector<int> out;
  for (size_t k = 0; k < detected.size(); ++k) {
    bool matches_truth = false, matches_ignored = false;
    for (const T& t : truth) matches_truth |= match(detected[k], t);
    for (const T& t : ignored) matches_ignored |= match(detected[k], t);
    if (matches_truth || !matches_ignored) out.push_back(static_cast<int>(k));
  }
  return out;
}

double Angle(const Eigen::Vector2d& from, const Eigen::Vector2d& to) {
  const Eigen::Vector2d d = to - from;
  return std::atan2(d.y(), d.x());
}

}  // namespace

TopViewTruth TruthInTopView(const sim::World& world, const SE2& T_map_vehicle,
                            const camera::TopViewFusion& fusion, const cv::Mat& mask,
                            double margin_px, double min_footprint_gap_px) {
  TopViewTruth truth;
  const SE2 T_vehicle_map = T_map_vehicle.inverse();
  const double reach_m = fusion.options().extent_m + 6.0;
  constexpr double kSharedM = 0.05;  // corners this close are one junction
  const auto shared = [&world](const Eigen::Vector2d& p, size_t self) {
    for (size_t k = 0; k < world.slots.size(); ++k) {
      if (k == self) continue;
      for (const Eigen::Vector2d& c : world.slots[k].corners_map) {
        if ((c - p).norm() < kSharedM) return true;
      }
    }
    return false;
  };
  const auto add_unique = [](std::vector<eval::LabelledMarkingPoint>* list,
                             const eval::LabelledMarkingPoint& p) {
    for (const eval::LabelledMarkingPoint& q : *list) {
      if ((q.px - p.px).norm() < 1.0) return;
    }
    list->push_back(p);
  };
  const render::GroundRasterOptions paint;
  for (size_t i = 0; i < world.slots.size(); ++i) {
    const sim::WorldSlot& slot = world.slots[i];
    if ((slot.corners_map[0] - T_map_vehicle.translation()).norm() > reach_m) continue;
    eval::SlotCornersPx px;
    for (size_t c = 0; c < 4; ++c)
      px[c] = fusion.VehicleToPixel(T_vehicle_map * slot.corners_map[c]);
    // Corner k's separating line runs to corner 3 - k (0-3, 1-2).
    std::array<bool, 4> in_view{}, in_image{};
    for (size_t c = 0; c < 4; ++c) {
      in_view[c] = InView(px[c], mask, margin_px, min_footprint_gap_px);
      in_image[c] = InView(px[c], mask, -10.0, 0.0);
      if (!in_image[c]) continue;
      eval::LabelledMarkingPoint p;
      p.px = px[c];
      p.direction_rad = Angle(px[c], px[3 - c]);
      p.is_t = shared(slot.corners_map[c], i);
      add_unique(c < 2 && in_view[c] ? &truth.marking_points : &truth.ignored_points, p);
    }
    if (!in_view[0] || !in_view[1]) {
      if (in_image[0] && in_image[1]) truth.ignored_entrances.push_back({px[0], px[1]});
      continue;
    }
    truth.entrances.push_back({px[0], px[1]});
    truth.corners.push_back(px);
    eval::SlotIdTruth id;
    id.id = slot.painted_id;
    id.readable = !slot.painted_id.empty() && slot.id_legible;
    if (id.readable) {
      const render::IdPlacement place = render::PlaceId(slot, paint);
      for (double u : {-0.5, 0.5}) {
        for (double v : {-0.5, 0.5}) {
          const Eigen::Vector2d corner_map = place.center_map +
                                             u * place.width_m * place.right_map +
                                             v * place.height_m * place.up_map;
          if (!InView(fusion.VehicleToPixel(T_vehicle_map * corner_map), mask, 2.0, 2.0)) {
            id.readable = false;
          }
        }
      }
    }
    truth.ids.push_back(id);
  }
  return truth;
}

std::vector<eval::LabelledMarkingPoint> AsLabelled(
    const std::vector<perception::MarkingPoint>& points) {
  std::vector<eval::LabelledMarkingPoint> out;
  for (const perception::MarkingPoint& p : points) {
    out.push_back({p.px, p.direction_rad, p.shape == perception::MarkingShape::kT});
  }
  return out;
}

std::vector<eval::EntranceLine> EntrancesOf(const std::vector<perception::DetectedSlot>& slots) {
  std::vector<eval::EntranceLine> out;
  for (const perception::DetectedSlot& s : slots) out.push_back({s.corners_px[0], s.corners_px[1]});
  return out;
}

std::vector<eval::SlotCornersPx> CornersOf(const std::vector<perception::DetectedSlot>& slots) {
  std::vector<eval::SlotCornersPx> out;
  for (const perception::DetectedSlot& s : slots) out.push_back(s.corners_px);
  return out;
}

std::vector<int> ScoredPoints(const std::vector<eval::LabelledMarkingPoint>& detected,
                              const std::vector<eval::LabelledMarkingPoint>& truth,
                              const std::vector<eval::LabelledMarkingPoint>& ignored) {
  return Scored(detected, truth, ignored,
                [](const auto& d, const auto& t) { return eval::MarkingPointsMatch(d, t); });
}

std::vector<int> ScoredSlots(const std::vector<eval::EntranceLine>& detected,
                             const std::vector<eval::EntranceLine>& truth,
                             const std::vector<eval::EntranceLine>& ignored) {
  return Scored(detected, truth, ignored,
                [](const auto& d, const auto& t) { return eval::EntranceLinesMatch(d, t); });
}

}  // namespace parkslam::harness
