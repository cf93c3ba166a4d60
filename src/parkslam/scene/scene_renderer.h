#ifndef PARKSLAM_SCENE_SCENE_RENDERER_H_
#define PARKSLAM_SCENE_SCENE_RENDERER_H_

// Colour camera images of a randomized scene (scene.h) through the car's
// rig, and their fusion into the top view by the same TopViewFusion the
// system uses (paper section III, Fig. 2).
//
// Per camera, a table computed once holds every pixel's ray: where it meets
// the floor (in an atlas of the floor at three resolutions, so that one
// remap samples the floor at the pixel's footprint), its direction for the
// solids, its vignetting, and whether the car's own body is in the way.
// Per scene: the floor is painted, every camera remaps it, the solids are
// ray cast in the azimuth wedges they cover, lamps mirror in a glossy
// floor, and each camera's exposure, white balance, blur, noise, dirt,
// glare and compression are applied before the fusion.

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "parkslam/camera/camera_model.h"
#include "parkslam/camera/camera_names.h"
#include "parkslam/camera/top_view.h"
#include "parkslam/scene/floor_painter.h"
#include "parkslam/scene/font_book.h"
#include "parkslam/scene/scene.h"

namespace parkslam::scene {

struct SceneRendererOptions {
  std::vector<std::string> fisheye_names = camera::FisheyeCameraNames();
  std::string front_camera = "front_mono";  // empty: none
  // Hard seams between the cameras, as ps2.0's surround views show them
  // (and a marking point in a seam shows once, not as two ghosts).
  camera::TopViewOptions top_view = [] {
    camera::TopViewOptions o;
    o.blend_angle_rad = 0.0;
    return o;
  }();
  // The floor: finest over the top view's square (and 0.2 m round it),
  // coarse out to where the fisheyes see it at all. The near floor's edges
  // lie on far pixels' edges, so that the far floor can hold it shrunk.
  double near_resolution_m = 0.02;
  double near_min_x_m = -3.8, near_max_x_m = 6.6, near_half_width_m = 5.2;
  double far_resolution_m = 0.2;
  double far_half_extent_m = 16.0;
  // Fusion with a stale calibration: this many perturbed copies of the rig
  // (Scene::fusion_calibration picks one), each camera turned and shifted
  // by these standard deviations.
  int perturbed_calibrations = 8;
  // Seam layouts (Scene::fusion_seams picks one): each camera's priority in
  // the fusion (camera::TopViewOptions::camera_priority_rad), in
  // fisheye_names' order. Real units let the side cameras cover more or
  // less of the corners.
  std::vector<std::vector<double>> seam_layouts = {
      {0, 0, 0, 0}, {0, 0, 0.25, 0.25}, {0, 0, 0.5, 0.5}};
  // Straight-seam layouts (camera::SeamStyle::kFootprintRays), after the
  // ones above: the seams' angle from the car's axis, front and rear.
  // ps2.0's views show about 0.3-0.6 rad (read off the real sample).
  std::vector<double> ray_seam_angles_rad = {0.3, 0.45, 0.6};
  double calibration_rotation_sigma_rad = 0.006;
  double calibration_translation_sigma_m = 0.015;
  std::uint64_t calibration_seed = 20261123;
  double ceiling_height_m = 3.0;

  bool IsValid(std::string* error) const;
};

// What to render besides the fused top view.
struct RenderRequest {
  bool fisheyes = false;    // whole fisheye images (else only what the top view samples)
  bool front = false;       // the front camera's image
  bool slot_paint = false;  // the fused clean slot-line coverage
  bool solids = false;      // the fused mask of solids (what hides the floor)
  bool dots = false;        // a dot on every marking point, fused (label checks)
  bool top_view = true;     // the fused view (RenderOnFloor only: Render always fuses)
};

struct RenderedScene {
  std::vector<cv::Mat> fisheyes;  // CV_8UC3, in the order of fisheye_names (see RenderRequest)
  cv::Mat top_view;               // CV_8UC3, before the scene's JPEG compression
  cv::Mat front;                  // CV_8UC3 when requested
  cv::Mat slot_paint;             // CV_8UC1 top view when requested
  cv::Mat solids;                 // CV_8UC1 top view when requested
  cv::Mat dots;                   // CV_8UC1 top view when requested
};

class SceneRenderer {
 public:
  // Throws std::invalid_argument for invalid options or a camera missing
  // from the rig.
  SceneRenderer(const camera::CameraRig& rig, const SceneRendererOptions& options = {});
  ~SceneRenderer();
  SceneRenderer(SceneRenderer&&) noexcept;
  SceneRenderer& operator=(SceneRenderer&&) noexcept;

  // Deterministic: the same scene gives the same bytes. `fonts` may be
  // null (no text is painted then).
  RenderedScene Render(const Scene& scene, FontBook* fonts,
                       const RenderRequest& request = {}) const;

  // One frame set of a car on a floor painted once (a lot's: lot_scene.h).
  // `view` holds what the car sees besides the floor, in the vehicle frame
  // (solids, tags, light, camera looks); the floor is `floor`'s, whose
  // frame holds the vehicle at yaw_rad and t (the car's pose in the map);
  // `light` is the light seen from the car (LightMap's turning
  // constructor). Fisheyes, front camera (with tags) and the fused view as
  // requested; no slot paint or dots. Deterministic as Render.
  RenderedScene RenderOnFloor(const Scene& view, const LightMap& light, const FloorAtlas& floor,
                              double yaw_rad, const Eigen::Vector2d& t,
                              const RenderRequest& request) const;

  // The top-view pixel (0-based) where the ground point p_vehicle shows in
  // the scene's fused view: seen by the true rig, fused with the scene's
  // calibration. Empty where no camera sees it.
  std::optional<Eigen::Vector2d> FusedPixelOf(const Scene& scene,
                                              const Eigen::Vector2d& p_vehicle) const;

  // The fusion that a scene's unit uses: its calibration and seam layout.
  // Built when first asked for (safe from any thread).
  const camera::TopViewFusion& FusionOf(const Scene& scene) const;
  // Builds the fusions now, on this many threads, so that rendering times
  // leave them out: every calibration's optical-axis layouts, and the
  // straight ones too if asked.
  void BuildFusions(int threads, bool straight_layouts) const;
  const SceneRendererOptions& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace parkslam::scene

#endif  // PARKSLAM_SCENE_SCENE_RENDERER_H_
