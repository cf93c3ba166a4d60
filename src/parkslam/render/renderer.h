#ifndef PARKSLAM_RENDER_RENDERER_H_
#define PARKSLAM_RENDER_RENDERER_H_

// Camera images of the simulated lot (paper section III): the four fisheye
// cameras see the painted ground, the front monocular camera sees the
// AprilTags on pillars and walls. A ray caster on per-camera lookup tables:
// every pixel's ray is computed once in the vehicle frame; per frame it is
// moved by the vehicle pose and meets the floor (the GroundRaster), a wall,
// a pillar, a parked car, a pedestrian, or the ceiling.
//
// Output: 8-bit grayscale (CV_8UC1) images of the camera's size.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "parkslam/camera/camera_model.h"
#include "parkslam/common/se2.h"
#include "parkslam/common/time.h"
#include "parkslam/render/ground_raster.h"
#include "parkslam/sensor/vehicle.h"
#include "parkslam/sim/world.h"

namespace parkslam::render {

struct RenderOptions {
  // Exposure and optics.
  double brightness = 1.0;    // gain on every pixel
  double uneven_light = 0.3;  // 0: even light; 1: pools of light under the lamps, dim between
  double overexposure_near_entrance =
      0.5;                     // daylight at the corridor's open end; 1: light x4 there
  double noise_sigma = 3.0;    // sensor noise, grey levels, new every frame
  double blur_sigma_px = 0.0;  // Gaussian blur of the image; 0: none
  double vignetting = 0.25;    // light fall-off at the edge of the field of view (share lost)

  // Scene.
  bool stains = true;    // oil stains and tyre marks on the floor (sets ground.stains)
  int parked_cars = 0;   // boxes in randomly chosen slots
  int pedestrians = 0;   // vertical cylinders in the aisles in front of random slots
  bool ego_body = true;  // the vehicle's own body, as the fisheyes see it
  VehicleParameters vehicle;
  double ego_body_height_m = 1.45;
  double wall_height_m = 2.8;  // walls and pillars reach the ceiling at this height
  double tag_center_height_m = 1.35;
  double tag_margin_cells = 1.0;  // white margin around the tag beyond libapriltag's own border
  double lamp_spacing_m = 6.0;    // ceiling lamps on a square grid
  double max_range_m = 25.0;      // nothing farther is drawn; haze from 70 % of it
  GroundRasterOptions ground;

  bool IsValid(std::string* error) const;
};

// A parked car: a box standing on the floor.
struct ParkedCar {
  int slot_index = -1;
  Eigen::Vector2d center_map = Eigen::Vector2d::Zero();
  double yaw_rad = 0.0;  // of its length axis
  double length_m = 4.6, width_m = 1.8, height_m = 1.5;
};

// A pedestrian: a vertical cylinder standing on the floor.
struct Pedestrian {
  Eigen::Vector2d center_map = Eigen::Vector2d::Zero();
  double radius_m = 0.25, height_m = 1.75;
};

// The 3D pose of the vehicle frame (z up, origin on the ground) in the map.
Eigen::Isometry3d VehiclePose3d(const SE2& T_map_vehicle);

// The centre of a tag in 3D map coordinates, at the options' mounting height.
Eigen::Vector3d TagCenter3d(const sim::WorldTag& tag, const RenderOptions& options);

class Renderer {
 public:
  // Draws the floor and computes every camera's lookup table (the expensive
  // part, once). Deterministic by seed: the floor's dirt, parked cars,
  // pedestrians and, with the frame time, the sensor noise. Throws
  // std::invalid_argument on invalid options or a tag ID outside tag36h11.
  Renderer(const sim::World& world, const camera::CameraRig& rig, const RenderOptions& options,
           std::uint64_t seed);
  ~Renderer();
  Renderer(Renderer&&) noexcept;
  Renderer& operator=(Renderer&&) noexcept;

  // The image of camera `camera_name` with the vehicle at T_map_vehicle at
  // time t_ns (the time seeds the noise: seed + t). Same inputs, same bytes.
  // Throws std::invalid_argument for a camera not in the rig.
  cv::Mat Render(const std::string& camera_name, const SE2& T_map_vehicle, TimeNs t_ns) const;
  std::vector<cv::Mat> RenderAll(const SE2& T_map_vehicle, TimeNs t_ns,
                                 const std::vector<std::string>& camera_names) const;

  const GroundRaster& ground() const;
  const RenderOptions& options() const;
  const std::vector<ParkedCar>& parked_cars() const;
  const std::vector<Pedestrian>& pedestrians() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace parkslam::render

#endif  // PARKSLAM_RENDER_RENDERER_H_
