#ifndef PARKSLAM_SCENE_FLOOR_PAINTER_H_
#define PARKSLAM_SCENE_FLOOR_PAINTER_H_

// The floor of a randomized scene as a colour raster: the material, the
// verge, decals and dirt, the painted slot lines and text, the light and
// the shadows. The renderer samples it wherever a camera ray meets the
// ground.

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "parkslam/scene/font_book.h"
#include "parkslam/scene/scene.h"

namespace parkslam::scene {

// Canvases hold radiance / kRadianceScale in 8 bits, so that light pools
// and glare up to twice the nominal white survive until the camera.
inline constexpr float kRadianceScale = 2.0f;

// A top-down raster of the floor in the vehicle frame: columns grow with
// x, rows with -y; integer pixel coordinates are pixel centres.
struct Canvas {
  double min_x_m = 0.0, max_y_m = 0.0, resolution_m = 0.02;
  cv::Mat bgr;  // CV_8UC3, radiance / kRadianceScale

  Canvas() = default;
  Canvas(double min_x, double max_y, double width_m, double height_m, double resolution);
  Eigen::Vector2d PixelOf(const Eigen::Vector2d& p_vehicle) const {
    return {(p_vehicle.x() - min_x_m) / resolution_m - 0.5,
            (max_y_m - p_vehicle.y()) / resolution_m - 0.5};
  }
};

// The light factor over the scene (1: nominal), on a 0.5 m grid, with its
// colour in the scene's tint; shadows are not in it.
class LightMap {
 public:
  // Over +-24 m round the origin (a scene round the car).
  explicit LightMap(const Lighting& light);
  // Over the rectangle [min_x, max_x] x [min_y, max_y] (a whole lot).
  LightMap(const Lighting& light, double min_x_m, double min_y_m, double max_x_m, double max_y_m);
  // `source` seen from another frame: the factor at p is source's at
  // R p + t (R turned by yaw_rad), over +-24 m round this frame's origin.
  // A lot's light seen from the car.
  LightMap(const LightMap& source, double yaw_rad, const Eigen::Vector2d& t);
  float At(double x_m, double y_m) const;
  // The factor resampled onto a canvas's pixels (CV_32F).
  cv::Mat OnCanvas(const Canvas& canvas) const;

 private:
  void Fill(const Lighting& light);
  cv::Mat grid_;  // CV_32F, rows grow with -y
  double min_x_m_ = -24.0, max_y_m_ = 24.0;
};

struct FloorPainterOptions {
  bool draw_text = true;
  bool dirt = true;
  // The dark under the car itself (at the origin); off for a floor that
  // the car drives over (a lot's, painted once).
  bool ego_shadow = true;
};

// Paints `scene`'s floor into `canvas` (its geometry set, its image
// overwritten). When slot_paint is given it receives the clean coverage of
// the slot lines (CV_8UC1, no wear, full opacity): where the labels'
// paint is.
void PaintFloor(const Scene& scene, const LightMap& light, const FloorPainterOptions& options,
                FontBook* fonts, Canvas* canvas, cv::Mat* slot_paint = nullptr);

// A floor painted once over a large area (a lot's, in the map frame) for
// cameras that move over it: level 0 at resolution_m, each further level
// half the one before (a mip chain), all in one image, so that one remap
// per camera samples every pixel at the level its footprint suits.
struct FloorAtlas {
  cv::Mat bgr;                   // CV_8UC3, radiance / kRadianceScale
  std::vector<cv::Rect> levels;  // level 0 on the left, the others stacked to its right
  double min_x_m = 0.0, max_y_m = 0.0, resolution_m = 0.02;

  // Where the floor point p lies in bgr, at the level that suits a pixel
  // footprint of footprint_m; (-10, -10) off the floor.
  cv::Point2f AtlasPixel(const Eigen::Vector2d& p, double footprint_m) const;
};

// Paints `scene`'s floor over [min_x, max_x] x [min_y, max_y] (the car's
// own shadow left out) and builds its levels. Throws std::invalid_argument
// when the area is empty or holds more than max_pixels at level 0.
FloorAtlas PaintFloorAtlas(const Scene& scene, const LightMap& light, FontBook* fonts,
                           double min_x_m, double min_y_m, double max_x_m, double max_y_m,
                           double resolution_m, int levels, double max_pixels = 4e7);

}  // namespace parkslam::scene

#endif  // PARKSLAM_SCENE_FLOOR_PAINTER_H_
