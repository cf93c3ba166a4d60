#ifndef PARKSLAM_SCENE_LOT_RENDERER_H_
#define PARKSLAM_SCENE_LOT_RENDERER_H_

// Drives through a whole lot in the scene renderer's look (paper section
// III: the four fisheyes and their fusion, the front camera and its tags).
// The lot (lot_scene.h) is built once: its floor with the paint, IDs, dirt,
// light and shadows painted into one atlas in the map frame; per frame only
// the car's pose, the cameras' exposure and noise, and what the car sees
// of the solids and tags change, so that every point of the floor looks
// the same from frame to frame.

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>

#include "parkslam/camera/camera_model.h"
#include "parkslam/common/se2.h"
#include "parkslam/common/time.h"
#include "parkslam/scene/floor_painter.h"
#include "parkslam/scene/lot_scene.h"
#include "parkslam/scene/scene_renderer.h"
#include "parkslam/sim/world.h"

namespace parkslam::scene {

struct LotRendererOptions {
  // The floor atlas: level 0's texel, the number of levels (each half the
  // one before), and the margin round the lot.
  double floor_resolution_m = 0.02;
  int floor_levels = 6;
  double floor_margin_m = 6.0;
  // Solids and tags farther than this from the car are left out of a frame.
  double view_range_m = 30.0;

  bool IsValid(std::string* error) const;
};

class LotRenderer {
 public:
  // Builds the lot and paints its floor (seconds for a large lot). Throws
  // std::invalid_argument for invalid options or look, a rig without the
  // cameras the renderer needs, or a lot too large for the atlas.
  LotRenderer(const sim::World& world, const camera::CameraRig& rig, const LotLook& look,
              const LotRendererOptions& options = {},
              const SceneRendererOptions& renderer_options = DriveRendererOptions());

  // The frame set at T_map_vehicle; t_ns seeds the cameras' noise.
  // Deterministic: the same pose and time give the same bytes.
  RenderedScene Render(const SE2& T_map_vehicle, TimeNs t_ns, const RenderRequest& request) const;

  const Scene& lot() const { return lot_; }
  const FloorAtlas& floor() const { return floor_; }
  const SceneRenderer& renderer() const { return *renderer_; }

  // A drive's renderer: no perturbed calibrations (the car's front end
  // fuses the fisheyes itself).
  static SceneRendererOptions DriveRendererOptions();

 private:
  // What the car sees besides the floor, in the vehicle frame.
  Scene ViewFrom(const SE2& T_map_vehicle, TimeNs t_ns) const;

  LotRendererOptions options_;
  Scene lot_;
  std::unique_ptr<LightMap> light_;
  FloorAtlas floor_;
  std::unique_ptr<SceneRenderer> renderer_;
};

}  // namespace parkslam::scene

#endif  // PARKSLAM_SCENE_LOT_RENDERER_H_
