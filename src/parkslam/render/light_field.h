#ifndef PARKSLAM_RENDER_LIGHT_FIELD_H_
#define PARKSLAM_RENDER_LIGHT_FIELD_H_

// The light in the lot for the renderer: ceiling lamps on a square grid and
// daylight at the openings in the walls (the corridor's outer end).

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <utility>
#include <vector>

#include "parkslam/sim/world.h"

namespace parkslam::render {

// Where the walls leave the lot open: pairs of wall ends that meet no other
// wall and lie less than 10 m apart (the corridor's outer end in the
// default world).
std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> WallOpenings(const sim::World& world);

struct LightFieldOptions {
  double lamp_spacing_m = 6.0;
  double lamp_height_m = 2.7;
  // 0: even light 1 everywhere; 1: the lamps' pattern alone (mean 1 in the
  // hall, pools under the lamps, dim between them).
  double uneven_light = 0.3;
  // Daylight gain 1 + 3 x this at an opening, falling off over 5 m.
  double overexposure_near_entrance = 0.5;
};

// A light factor (1: nominal) over the rectangle [min_x, min_x + width] x
// [max_y - height, max_y] of the map, on a 0.25 m grid.
class LightField {
 public:
  LightField(const sim::World& world, double min_x_m, double max_y_m, double width_m,
             double height_m, const LightFieldOptions& options);

  // Bilinear in the grid; clamped at its border.
  float At(double x_m, double y_m) const;
  // True under a lamp tube (1.2 m along x, 0.12 m wide) on the ceiling.
  bool IsLamp(float x_m, float y_m) const;

 private:
  float spacing_m_, inv_spacing_, lamp_x0_m_, lamp_y0_m_;
  double min_x_m_, max_y_m_;
  cv::Mat grid_;  // CV_32F, north up
};

}  // namespace parkslam::render

#endif  // PARKSLAM_RENDER_LIGHT_FIELD_H_
