#ifndef PARKSLAM_CAMERA_TOP_VIEW_H_
#define PARKSLAM_CAMERA_TOP_VIEW_H_

// Surround-view fusion (paper III, Fig. 2): the four fisheye images become
// one top-view image of the ground around the car. Lookup tables are
// computed once from the rig; each fusion is then two fixed-point remaps
// (the best and the second-best camera of every top-view pixel) and a
// feathered blend where two cameras overlap.
//
// Top-view convention (as the ps2.0 data set): the car points up; image x
// to the right is the vehicle's -y (its right side), image y down is the
// vehicle's -x; size_px pixels span extent_m metres (600 px for 10 m:
// 1.667 cm a pixel), centred center_x_m ahead of the rear axle.

#include <array>
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

#include "parkslam/camera/camera_model.h"

namespace parkslam::camera {

// Where the seams between the cameras lie.
// - kOpticalAxis: every ground point comes from the camera that sees it
//   closest to its optical axis. The seams curve, and the front and rear
//   cameras' parts narrow away from the car.
// - kFootprintRays: straight seams leave the footprint's four corners
//   outwards, at seam_front_angle_rad (seam_rear_angle_rad) from the car's
//   axis. The front and rear cameras own the wedges between them, which
//   widen away from the car. That is how ps2.0's views and many
//   surround-view units draw them.
// A camera's role (front, rear, left, right) is read from its optical axis
// in the vehicle frame. Where the role's camera does not see a point, the
// optical-axis rule decides.
enum class SeamStyle { kOpticalAxis, kFootprintRays };
// Every style with its name, for the options file (io/visit_yaml.h).
inline constexpr std::array<std::pair<SeamStyle, const char*>, 2> EnumNames(SeamStyle) {
  return {
      {{SeamStyle::kOpticalAxis, "optical_axis"}, {SeamStyle::kFootprintRays, "footprint_rays"}}};
}

struct TopViewOptions {
  int size_px = 600;
  double extent_m = 10.0;
  double center_x_m = 1.4;
  // Cameras are weighted by how close to their optical axis they see a
  // point; within this angle of the best camera's weight the second one is
  // blended in (a feathered seam). With kFootprintRays: within this angle
  // of the seam, seen from its corner.
  double blend_angle_rad = 0.3;
  SeamStyle seam_style = SeamStyle::kOpticalAxis;
  double seam_front_angle_rad = 0.6;  // kFootprintRays only; in (0, pi/2)
  double seam_rear_angle_rad = 0.6;
  // Optional, one per camera in camera_names' order: added to a camera's
  // weight, so that it wins over a wider area (empty: all zero). Real units
  // draw their seams in their own places; this moves ours.
  std::vector<double> camera_priority_rad;
  bool mask_footprint = true;
  double footprint_length_m = 4.7;
  double footprint_width_m = 1.85;
  double footprint_rear_overhang_m = 1.0;

  bool IsValid(std::string* error) const;

  // The field list, walked by the options file reader (io/options_yaml.h).
  template <typename V>
  void VisitFields(V& v) {
    v("size_px", size_px);
    v("extent_m", extent_m);
    v("center_x_m", center_x_m);
    v("blend_angle_rad", blend_angle_rad);
    v("camera_priority_rad", camera_priority_rad);
    v("seam_style", seam_style);
    v("seam_front_angle_rad", seam_front_angle_rad);
    v("seam_rear_angle_rad", seam_rear_angle_rad);
    v("mask_footprint", mask_footprint);
    v("footprint_length_m", footprint_length_m);
    v("footprint_width_m", footprint_width_m);
    v("footprint_rear_overhang_m", footprint_rear_overhang_m);
  }
};

// How a top-view pixel takes its value from a camera's image: bilinear
// interpolation (the default), or the nearest pixel, as surround-view units
// with plain lookup tables do (their lines come out jagged and sharp).
enum class FusionLookup { kBilinear, kNearest };

class TopViewFusion {
 public:
  // `fusion_rig` holds the extrinsics used for fusion: pass a perturbed copy
  // of the true rig to simulate calibration that degrades with time.
  // Throws std::invalid_argument for a missing camera or invalid options.
  TopViewFusion(const CameraRig& fusion_rig, const std::vector<std::string>& camera_names,
                const TopViewOptions& options = {});

  // One 8-bit image (grey or BGR, all alike) per camera, in the order of
  // camera_names. Throws std::invalid_argument naming the camera when an
  // image has the wrong size or type.
  cv::Mat Fuse(const std::vector<cv::Mat>& images,
               FusionLookup lookup = FusionLookup::kBilinear) const;

  // Top-view pixel (0-based, centre of the top-left pixel at (0, 0)) of a
  // ground point in the vehicle frame, and back.
  Eigen::Vector2d VehicleToPixel(const Eigen::Vector2d& p_vehicle) const;
  Eigen::Vector2d PixelToVehicle(const Eigen::Vector2d& pixel) const;

  // The index (into camera_names) of the camera that a top-view pixel
  // takes most of its value from; -1 where no camera sees the ground.
  int PrimaryCamera(int u, int v) const;
  // The blend at a top-view pixel: the primary camera's share of the value
  // (0.5 to 1) and the second camera (-1 where the primary is alone).
  double PrimaryWeight(int u, int v) const;
  int SecondaryCamera(int u, int v) const;

  const TopViewOptions& options() const { return options_; }

 private:
  TopViewOptions options_;
  std::vector<std::string> names_;
  std::vector<cv::Size> sizes_;
  int stacked_width_ = 0, stacked_height_ = 0;
  // Maps into the stacked input (cameras one below the other): the best
  // camera, the second best; fixed point as cv::convertMaps makes them.
  cv::Mat primary_xy_, primary_frac_, secondary_xy_, secondary_frac_;
  // Each camera's first row in the stacked input, for rounding a map to the
  // nearest pixel within the camera it reads (FusionLookup::kNearest).
  std::vector<int> row_offsets_;
  cv::Mat primary_weight_;    // CV_16U, 256: the best camera alone
  cv::Mat valid_;             // CV_8U, 0 where no camera sees the ground (or the car)
  cv::Mat primary_camera_;    // CV_8S, the best camera's index, -1 where none
  cv::Mat secondary_camera_;  // CV_8S, the blended second camera, -1 where none
};

// A world-to-camera perturbation of a rig's extrinsics: each camera is
// rotated by small roll, pitch, yaw angles and shifted, as an old
// calibration would be off.
CameraRig PerturbExtrinsics(const CameraRig& rig, double rotation_sigma_rad,
                            double translation_sigma_m, std::uint64_t seed);

}  // namespace parkslam::camera

#endif  // PARKSLAM_CAMERA_TOP_VIEW_H_
