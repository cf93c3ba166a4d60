#include "parkslam/scene/lot_renderer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "parkslam/common/angles.h"
#include "parkslam/common/seed_mix.h"
#include "parkslam/scene/font_book.h"

namespace parkslam::scene {
namespace {

// The lot's painted extent: its strokes, texts, decals and solids.
void LotExtent(const Scene& lot, Eigen::Vector2d* min, Eigen::Vector2d* max) {
  *min = Eigen::Vector2d::Constant(1e18);
  *max = Eigen::Vector2d::Constant(-1e18);
  const auto add = [&](const Eigen::Vector2d& p, double r) {
    *min = min->cwiseMin(p - Eigen::Vector2d::Constant(r));
    *max = max->cwiseMax(p + Eigen::Vector2d::Constant(r));
  };
  for (const Stroke& s : lot.strokes) {
    add(s.a, s.width_m);
    add(s.b, s.width_m);
  }
  for (const FloorText& t : lot.texts) add(t.center, t.height_m);
  for (const Solid& s : lot.solids) {
    // The box's own extent (a long wall is long one way only).
    const double c = std::abs(std::cos(s.yaw_rad)), n = std::abs(std::sin(s.yaw_rad));
    *min = min->cwiseMin(s.center -
                         Eigen::Vector2d(c * s.half_x + n * s.half_y, n * s.half_x + c * s.half_y));
    *max = max->cwiseMax(s.center +
                         Eigen::Vector2d(c * s.half_x + n * s.half_y, n * s.half_x + c * s.half_y));
  }
  if (min->x() > max->x()) {
    *min = Eigen::Vector2d::Constant(-1.0);
    *max = Eigen::Vector2d::Constant(1.0);
  }
}

}  // namespace

bool LotRendererOptions::IsValid(std::string* error) const {
  const auto fail = [error](const char* what) {
    if (error != nullptr) *error = what;
    return false;
  };
  if (!(floor_resolution_m >= 0.005 && floor_resolution_m <= 0.2))
    return fail("floor_resolution_m must be in [0.005, 0.2]");
  if (floor_levels < 1 || floor_levels > 8) return fail("floor_levels must be in [1, 8]");
  if (!(floor_margin_m >= 0 && floor_margin_m <= 100))
    return fail("floor_margin_m must be in [0, 100]");
  if (!(view_range_m > 1 && view_range_m <= 200)) return fail("view_range_m must be in (1, 200]");
  return true;
}

SceneRendererOptions LotRenderer::DriveRendererOptions() {
  SceneRendererOptions o;
  o.perturbed_calibrations = 0;
  return o;
}

LotRenderer::LotRenderer(const sim::World& world, const camera::CameraRig& rig, const LotLook& look,
                         const LotRendererOptions& options,
                         const SceneRendererOptions& renderer_options)
    : options_(options) {
  std::string error;
  if (!options_.IsValid(&error)) throw std::invalid_argument("lot renderer: " + error);
  lot_ = BuildLotScene(world, look);
  Eigen::Vector2d min, max;
  LotExtent(lot_, &min, &max);
  min -= Eigen::Vector2d::Constant(options_.floor_margin_m);
  max += Eigen::Vector2d::Constant(options_.floor_margin_m);
  light_ = std::make_unique<LightMap>(lot_.light, min.x(), min.y(), max.x(), max.y());
  FontBook fonts(FindFloorFonts());
  floor_ = PaintFloorAtlas(lot_, *light_, &fonts, min.x(), min.y(), max.x(), max.y(),
                           options_.floor_resolution_m, options_.floor_levels);
  renderer_ = std::make_unique<SceneRenderer>(rig, renderer_options);
}

Scene LotRenderer::ViewFrom(const SE2& T_map_vehicle, TimeNs t_ns) const {
  const SE2 T_vehicle_map = T_map_vehicle.inverse();
  const double yaw = T_map_vehicle.yaw();
  const Eigen::Vector2d car = T_map_vehicle.translation();
  Scene view;
  view.seed = lot_.seed;
  view.floor = lot_.floor;
  view.light = lot_.light;
  view.light.lamp_offset = T_vehicle_map * lot_.light.lamp_offset;
  view.light.lamp_grid_yaw_rad = NormalizeAngle(lot_.light.lamp_grid_yaw_rad - yaw);
  view.light.sun_azimuth_rad = NormalizeAngle(lot_.light.sun_azimuth_rad - yaw);
  view.light.backlight_dir = T_vehicle_map.rotation() * lot_.light.backlight_dir;
  // Each frame its own noise: the cameras' seeds mixed with the time.
  const auto frame_seed = static_cast<std::uint64_t>(t_ns);
  view.cameras = lot_.cameras;
  for (CameraLook& c : view.cameras) c.seed = MixSeed(c.seed, frame_seed);
  view.front_camera = lot_.front_camera;
  view.front_camera.seed = MixSeed(view.front_camera.seed, frame_seed);
  const double range = options_.view_range_m;
  for (const Solid& s : lot_.solids) {
    if ((s.center - car).norm() - std::hypot(s.half_x, s.half_y) > range) continue;
    Solid v = s;
    v.center = T_vehicle_map * s.center;
    v.yaw_rad = NormalizeAngle(s.yaw_rad - yaw);
    view.solids.push_back(v);
  }
  for (const WallTag& t : lot_.tags) {
    if ((t.center - car).norm() > range) continue;
    WallTag v = t;
    v.center = T_vehicle_map * t.center;
    v.normal_yaw_rad = NormalizeAngle(t.normal_yaw_rad - yaw);
    view.tags.push_back(v);
  }
  return view;
}

RenderedScene LotRenderer::Render(const SE2& T_map_vehicle, TimeNs t_ns,
                                  const RenderRequest& request) const {
  const Scene view = ViewFrom(T_map_vehicle, t_ns);
  const LightMap light(*light_, T_map_vehicle.yaw(), T_map_vehicle.translation());
  return renderer_->RenderOnFloor(view, light, floor_, T_map_vehicle.yaw(),
                                  T_map_vehicle.translation(), request);
}

}  // namespace parkslam::scene
