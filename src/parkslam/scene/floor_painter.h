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
  explicit LightMap(const Lighting& light);
  float At(double x_m, double y_m) const;
  // The factor resampled onto a canvas's pixels (CV_32F).
  cv::Mat OnCanvas(const Canvas& canvas) const;

 private:
  cv::Mat grid_;  // CV_32F
};

struct FloorPainterOptions {
  bool draw_text = true;
  bool dirt = true;
};

// Paints `scene`'s floor into `canvas` (its geometry set, its image
// overwritten). When slot_paint is given it receives the clean coverage of
// the slot lines (CV_8UC1, no wear, full opacity): where the labels'
// paint is.
void PaintFloor(const Scene& scene, const LightMap& light, const FloorPainterOptions& options,
                FontBook* fonts, Canvas* canvas, cv::Mat* slot_paint = nullptr);

}  // namespace parkslam::scene

#endif  // PARKSLAM_SCENE_FLOOR_PAINTER_H_
