#ifndef PARKSLAM_RENDER_GROUND_RASTER_H_
#define PARKSLAM_RENDER_GROUND_RASTER_H_

// The floor of the lot as a top-down grayscale raster: concrete, painted
// slot lines and slot IDs (paper III-A: the fisheye cameras see the ground),
// dirt, and the footprints of walls and pillars. The renderer samples it
// wherever a camera ray meets the ground.

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

#include "parkslam/sim/world.h"

namespace parkslam::render {

struct GroundRasterOptions {
  double resolution_m = 0.02;  // edge of one raster pixel
  double margin_m = 2.0;       // around the world's bounding box

  // Concrete, in grey levels (0..255).
  double concrete_grey = 96.0;
  double shading_amplitude_grey = 14.0;  // unevenness over about 4 m
  double mottling_amplitude_grey = 5.0;  // unevenness over about 0.5 m
  double grain_sigma_grey = 4.0;         // per raster pixel

  // Paint. Slot lines run along both separating sides and the back of every
  // slot; the entrance is left open except for stubs of the entrance line at
  // its two corners, which make the T junctions between neighbouring slots
  // and the L junctions at the ends of a row (ps2.0 marking points).
  double paint_grey = 225.0;
  double line_width_m = 0.15;
  double entrance_stub_m = 0.5;  // 0: no stubs, the separating lines end freely
  // Painted IDs: seven-segment digits inside the slot, their foot
  // id_setback_m behind the entrance, upright for a reader in the aisle.
  double id_height_m = 0.6;
  double id_setback_m = 0.3;
  double worn_id_opacity = 0.4;          // paint left on a worn ID
  double worn_id_broken_fraction = 0.3;  // share of a worn ID's box flaked off

  // Dirt: oil stains (mostly inside slots) and tyre marks at slot entrances.
  bool stains = true;
  double stains_per_100m2 = 1.5;
  double tyre_marks_per_slot = 0.3;

  double wall_thickness_m = 0.2;  // walls are drawn black, centred on their segment

  bool IsValid(std::string* error) const;
};

// Where and how large a slot's painted ID is drawn: the rectangle of its
// digits, in the map frame. Reading direction `right_map` runs from the
// slot's corner 0 towards corner 1; `up_map` points from the foot of the
// digits to their top, into the slot along its sides.
struct IdPlacement {
  Eigen::Vector2d center_map = Eigen::Vector2d::Zero();
  Eigen::Vector2d right_map = Eigen::Vector2d::UnitX();
  Eigen::Vector2d up_map = Eigen::Vector2d::UnitY();
  double width_m = 0.0;
  double height_m = 0.0;
};

// The placement of `slot`'s painted ID (its width from the number of
// characters of painted_id; zero width for a slot without an ID).
IdPlacement PlaceId(const sim::WorldSlot& slot, const GroundRasterOptions& options);

class GroundRaster {
 public:
  // Draws the floor of `world`. Deterministic by seed (concrete, dirt and the
  // flaking of worn IDs). Throws std::invalid_argument on invalid options.
  GroundRaster(const sim::World& world, const GroundRasterOptions& options, std::uint64_t seed);

  // CV_8UC1; north up: columns grow with map x, rows grow with -y.
  const cv::Mat& image() const { return image_; }
  const GroundRasterOptions& options() const { return options_; }
  double resolution_m() const { return options_.resolution_m; }
  // Map coordinates of the raster's outer top-left corner (min x, max y).
  double min_x_m() const { return min_x_m_; }
  double max_y_m() const { return max_y_m_; }

  // Continuous pixel coordinates (column, row) of a map point; integer
  // values are pixel centres.
  Eigen::Vector2d PixelOf(const Eigen::Vector2d& p_map) const;
  Eigen::Vector2d MapOf(const Eigen::Vector2d& pixel) const;
  // The grey level of the pixel holding p_map; 0 outside the raster.
  std::uint8_t At(const Eigen::Vector2d& p_map) const;

 private:
  GroundRasterOptions options_;
  double min_x_m_ = 0.0;
  double max_y_m_ = 0.0;
  cv::Mat image_;
};

}  // namespace parkslam::render

#endif  // PARKSLAM_RENDER_GROUND_RASTER_H_
