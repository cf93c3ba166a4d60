#include "parkslam/viz/map_svg.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "parkslam/viz/svg.h"

namespace parkslam::viz {
namespace {

constexpr double kBorderM = 3.0;
constexpr double kMinWidthM = 14.0;  // room for the 10 m scale bar
constexpr double kMinHeightM = 6.0;
constexpr double kCanvasMarginPx = 30.0;
constexpr double kScaleBarM = 10.0;
constexpr std::size_t kMaxTrajectoryPoints = 5000;
constexpr double kTrajectoryMinSpacingPx = 0.5;

constexpr const char* kObstacleFill = "#555555";
constexpr const char* kObstacleStroke = "#333333";
constexpr const char* kSlotColor = "#2f6f4f";
constexpr const char* kSlotIdColor = "black";
constexpr const char* kTemporaryIdColor = "orange";
constexpr const char* kIllegibleIdColor = "#999999";
constexpr const char* kTagColor = "#1f5fbf";
constexpr const char* kGuessedEdgeDash = "4 3";

double Clamp(double value, double lo, double hi) { return std::min(std::max(value, lo), hi); }

// --- Bounds ---------------------------------------------------------------

void Extend(const Eigen::Vector2d& p, Eigen::AlignedBox2d* box) {
  if (p.allFinite()) box->extend(p);
}

Eigen::AlignedBox2d WorldBounds(const SemanticMap& map,
                                const std::vector<SvgTrajectory>& trajectories) {
  Eigen::AlignedBox2d box;  // empty
  for (const MapSlot& slot : map.slots) {
    for (const Eigen::Vector2d& corner : slot.corners_map) Extend(corner, &box);
  }
  for (const MapObstacle& obstacle : map.obstacles) {
    for (const Eigen::Vector2d& p : obstacle.points_map) Extend(p, &box);
  }
  for (const MapTag& tag : map.tags) Extend(tag.p_map, &box);
  for (const SvgTrajectory& t : trajectories) {
    for (const TimedPose& pose : t.trajectory) {
      Extend(pose.T_map_vehicle.translation(), &box);
    }
  }
  if (box.isEmpty()) box.extend(Eigen::Vector2d::Zero());

  const Eigen::Vector2d center = box.center();
  const Eigen::Vector2d half_size = (0.5 * box.sizes().array() + kBorderM)
                                        .max(Eigen::Array2d(0.5 * kMinWidthM, 0.5 * kMinHeightM))
                                        .matrix();
  return Eigen::AlignedBox2d(center - half_size, center + half_size);
}

// --- Obstacles ------------------------------------------------------------

void DrawObstacles(const SemanticMap& map, SvgCanvas* canvas) {
  canvas->BeginGroup({.stroke = kObstacleStroke}, "obstacles");
  const SvgStyle pillar{.fill = kObstacleFill, .width_px = 1.0};
  const SvgStyle wall{.width_px = 4.0};
  for (const MapObstacle& obstacle : map.obstacles) {
    if (obstacle.kind == ObstacleKind::kPillar && obstacle.points_map.size() >= 3) {
      canvas->Polygon(obstacle.points_map, pillar);
    } else {
      canvas->Polyline(obstacle.points_map, wall);
    }
  }
  canvas->EndGroup();
}

// --- Slots ----------------------------------------------------------------

void DrawSlotOutline(const MapSlot& slot, SvgCanvas* canvas) {
  for (int k = 0; k < kSlotCorners; ++k) {
    const int next = (k + 1) % kSlotCorners;
    const bool entrance = (k == 0);  // corners 0-1 (sensor_data.h)
    const bool touches_guessed = !slot.corner_observed[k] || !slot.corner_observed[next];
    SvgStyle edge;
    if (entrance) edge.width_px = 3.0;
    if (touches_guessed) edge.dash = kGuessedEdgeDash;
    canvas->Line(slot.corners_map[k], slot.corners_map[next], edge);
  }
  const SvgStyle observed{.fill = kSlotColor};
  const SvgStyle guessed{.fill = "white", .width_px = 1.0};
  for (int k = 0; k < kSlotCorners; ++k) {
    if (slot.corner_observed[k]) {
      canvas->Circle(slot.corners_map[k], 2.0, observed);
    } else {
      canvas->Circle(slot.corners_map[k], 3.0, guessed);
    }
  }
}

const char* SlotIdColor(const MapSlot& slot) {
  if (slot.temporary) return kTemporaryIdColor;
  if (!slot.id_legible) return kIllegibleIdColor;
  return kSlotIdColor;
}

// Inside the slot, a little behind the middle of its entrance line. The text
// stays horizontal, so it is upright whatever the slot's heading.
Eigen::Vector2d SlotIdAnchor(const MapSlot& slot) {
  const Eigen::Vector2d entrance_mid = 0.5 * (slot.corners_map[0] + slot.corners_map[1]);
  const Eigen::Vector2d back_mid = 0.5 * (slot.corners_map[2] + slot.corners_map[3]);
  return entrance_mid + 0.3 * (back_mid - entrance_mid);
}

void DrawSlots(const SemanticMap& map, SvgCanvas* canvas) {
  canvas->BeginGroup({.stroke = kSlotColor, .fill = "none", .width_px = 1.2}, "slots");
  for (const MapSlot& slot : map.slots) DrawSlotOutline(slot, canvas);
  canvas->EndGroup();
}

void DrawSlotIds(const SemanticMap& map, SvgCanvas* canvas) {
  const double font_px = Clamp(0.9 * canvas->pixels_per_m(), 7.0, 28.0);
  canvas->BeginGroup({.font_size_px = font_px, .text_anchor = "middle"}, "slot_ids");
  for (const MapSlot& slot : map.slots) {
    if (slot.id.empty()) continue;
    canvas->Text(SlotIdAnchor(slot), slot.id,
                 {.fill = SlotIdColor(slot), .center_vertically = true});
  }
  canvas->EndGroup();
}

// --- Tags -----------------------------------------------------------------

std::vector<Eigen::Vector2d> TagSquare(const MapTag& tag, double side_m) {
  const Eigen::Rotation2Dd R_map_tag(tag.yaw_map_rad);
  std::vector<Eigen::Vector2d> corners;
  for (const auto& [u, v] :
       {std::pair{1.0, 1.0}, std::pair{-1.0, 1.0}, std::pair{-1.0, -1.0}, std::pair{1.0, -1.0}}) {
    corners.push_back(tag.p_map + R_map_tag * Eigen::Vector2d(u, v) * (0.5 * side_m));
  }
  return corners;
}

void DrawTags(const SemanticMap& map, SvgCanvas* canvas) {
  const double ppm = canvas->pixels_per_m();
  const double min_side_m = 4.0 / ppm;
  const double normal_m = std::max(1.0, 8.0 / ppm);
  const double font_px = Clamp(0.8 * ppm, 6.0, 20.0);
  canvas->BeginGroup({.stroke = kTagColor, .fill = kTagColor}, "tags");
  for (const MapTag& tag : map.tags) {
    const Eigen::Vector2d normal(std::cos(tag.yaw_map_rad), std::sin(tag.yaw_map_rad));
    canvas->Polygon(TagSquare(tag, std::max(tag.size_m, min_side_m)), {.width_px = 0.5});
    canvas->Line(tag.p_map, tag.p_map + normal_m * normal, {.width_px = 1.5});
    canvas->Text(tag.p_map + (normal_m + font_px / ppm) * normal, std::to_string(tag.tag_id),
                 {.stroke = "none",
                  .font_size_px = font_px,
                  .text_anchor = "middle",
                  .center_vertically = true});
  }
  canvas->EndGroup();
}

// --- Trajectories, legend, scale bar, title ---------------------------------

std::vector<Eigen::Vector2d> Positions(const Trajectory& trajectory) {
  std::vector<Eigen::Vector2d> positions;
  positions.reserve(trajectory.size());
  for (const TimedPose& pose : trajectory) {
    const Eigen::Vector2d& p = pose.T_map_vehicle.translation();
    if (p.allFinite()) positions.push_back(p);
  }
  return positions;
}

void DrawTrajectories(const std::vector<SvgTrajectory>& trajectories, SvgCanvas* canvas) {
  const double min_spacing_m = kTrajectoryMinSpacingPx / canvas->pixels_per_m();
  canvas->BeginGroup({.width_px = 1.5, .opacity = 0.9}, "trajectories");
  for (const SvgTrajectory& t : trajectories) {
    const std::vector<Eigen::Vector2d> points =
        DecimatePolyline(Positions(t.trajectory), min_spacing_m, kMaxTrajectoryPoints);
    if (points.empty()) continue;
    canvas->Polyline(points, {.stroke = t.color});
    canvas->Circle(points.front(), 3.0, {.fill = t.color});  // the start
  }
  canvas->EndGroup();
}

// Pixel positions go through ToMap: the canvas draws in map coordinates.
// The legend is one row in the bottom margin, right of the scale bar, so it
// never covers the map.
void DrawLegend(const std::vector<SvgTrajectory>& trajectories, SvgCanvas* canvas) {
  if (trajectories.empty()) return;
  constexpr double kPadPx = 8.0, kSamplePx = 22.0, kCharPx = 7.0, kFontPx = 12.0;
  const double y_px = canvas->height_px() - 14.0;
  double x_px = kCanvasMarginPx + kScaleBarM * canvas->pixels_per_m() + 4.0 * kPadPx;
  auto at = [canvas](double x, double y) { return canvas->ToMap(Eigen::Vector2d(x, y)); };
  canvas->BeginGroup({.font_size_px = kFontPx}, "legend");
  for (const SvgTrajectory& t : trajectories) {
    if (t.label.empty()) continue;  // drawn, but not listed
    canvas->Line(at(x_px, y_px), at(x_px + kSamplePx, y_px), {.stroke = t.color, .width_px = 3.0});
    canvas->Text(at(x_px + kSamplePx + kPadPx, y_px), t.label,
                 {.fill = "black", .center_vertically = true});
    x_px += kSamplePx + 3.0 * kPadPx + kCharPx * static_cast<double>(t.label.size());
  }
  canvas->EndGroup();
}

void DrawScaleBar(SvgCanvas* canvas) {
  const double length_px = kScaleBarM * canvas->pixels_per_m();
  const double y_px = canvas->height_px() - 10.0;
  const double left_px = kCanvasMarginPx;
  const double right_px = left_px + length_px;
  auto at = [canvas](double x_px, double y) { return canvas->ToMap(Eigen::Vector2d(x_px, y)); };
  canvas->BeginGroup({.stroke = "black", .width_px = 1.5}, "scale_bar");
  canvas->Line(at(left_px, y_px), at(right_px, y_px), {});
  canvas->Line(at(left_px, y_px - 5.0), at(left_px, y_px), {});
  canvas->Line(at(right_px, y_px - 5.0), at(right_px, y_px), {});
  canvas->Text(at(0.5 * (left_px + right_px), y_px - 4.0), "10 m",
               {.stroke = "none", .fill = "black", .font_size_px = 11.0, .text_anchor = "middle"});
  canvas->EndGroup();
}

void DrawTitle(const std::string& title, SvgCanvas* canvas) {
  if (title.empty()) return;
  canvas->Text(canvas->ToMap(Eigen::Vector2d(kCanvasMarginPx, 20.0)), title,
               {.fill = "black", .font_size_px = 16.0, .font_weight = "bold"});
}

}  // namespace

std::vector<Eigen::Vector2d> DecimatePolyline(const std::vector<Eigen::Vector2d>& points,
                                              double min_spacing, std::size_t max_points) {
  max_points = std::max<std::size_t>(max_points, 2);
  std::vector<Eigen::Vector2d> spaced;
  spaced.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const bool last = (i + 1 == points.size());
    if (spaced.empty() || last || (points[i] - spaced.back()).norm() >= min_spacing) {
      spaced.push_back(points[i]);
    }
  }
  if (spaced.size() <= max_points) return spaced;

  // Index k of the output takes input k * (n - 1) / (m - 1): first and last
  // included, at most m points.
  std::vector<Eigen::Vector2d> out;
  out.reserve(max_points);
  const std::size_t n = spaced.size();
  for (std::size_t k = 0; k < max_points; ++k) {
    out.push_back(spaced[k * (n - 1) / (max_points - 1)]);
  }
  return out;
}

std::string RenderMapSvg(const SemanticMap& map, const std::vector<SvgTrajectory>& trajectories,
                         const MapSvgOptions& options) {
  if (!(options.pixels_per_m > 0.0)) {
    throw std::invalid_argument("RenderMapSvg: pixels_per_m must be > 0");
  }
  const Eigen::AlignedBox2d box = WorldBounds(map, trajectories);
  SvgCanvas canvas(box.min(), box.max(), options.pixels_per_m, kCanvasMarginPx);
  DrawObstacles(map, &canvas);
  DrawSlots(map, &canvas);
  DrawTrajectories(trajectories, &canvas);
  if (options.draw_slot_ids) DrawSlotIds(map, &canvas);
  DrawTags(map, &canvas);
  DrawLegend(trajectories, &canvas);
  DrawScaleBar(&canvas);
  DrawTitle(options.title, &canvas);
  return canvas.Finish();
}

}  // namespace parkslam::viz
