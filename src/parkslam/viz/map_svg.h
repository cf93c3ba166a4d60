#ifndef PARKSLAM_VIZ_MAP_SVG_H_
#define PARKSLAM_VIZ_MAP_SVG_H_

// A top-down picture of a SemanticMap with trajectories over it, as an SVG
// document in a string.

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "parkslam/common/trajectory.h"
#include "parkslam/map/semantic_map.h"

namespace parkslam::viz {

struct SvgTrajectory {
  std::string label = "";  // shown in the legend; empty: drawn but not listed
  std::string color = "";  // any SVG colour: "#d62728", "green"
  Trajectory trajectory = {};
};

struct MapSvgOptions {
  double pixels_per_m = 10.0;
  bool draw_slot_ids = true;
  std::string title = "";
};

// Draws obstacles (pillars filled, walls as thick lines), slots (entrance
// side thicker; observed corners as dots, guessed ones as rings, edges at a
// guessed corner dashed; IDs black, temporary IDs orange, illegible ground
// truth IDs grey), tags (blue squares with their outward normal and id),
// the trajectories (each decimated to at most 5000 points), a legend, a 10 m
// scale bar and the title. The picture covers the map and the trajectories
// with a 3 m border. Throws std::invalid_argument for pixels_per_m <= 0.
std::string RenderMapSvg(const SemanticMap& map, const std::vector<SvgTrajectory>& trajectories,
                         const MapSvgOptions& options = {});

// Thins a polyline for drawing: drops points closer than min_spacing to the
// last kept one, then keeps at most max_points (>= 2) evenly spread by index.
// The first and last points always stay.
std::vector<Eigen::Vector2d> DecimatePolyline(const std::vector<Eigen::Vector2d>& points,
                                              double min_spacing, std::size_t max_points);

}  // namespace parkslam::viz

#endif  // PARKSLAM_VIZ_MAP_SVG_H_
