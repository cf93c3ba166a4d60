#ifndef PARKSLAM_PERCEPTION_TAG_DETECTOR_H_
#define PARKSLAM_PERCEPTION_TAG_DETECTOR_H_

// AprilTag localization in the front camera (paper III-B): libapriltag
// (tag36h11) finds the tags; PnP (IPPE square, both solutions) gives each
// tag's pose; the direct angle alpha = atan((x_i - x_0) / f) of the tag
// centre checks the PnP solution; d = |t|; the tag lies at
// x = sin(alpha) d (right), y = cos(alpha) d (ahead) from the camera.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "parkslam/camera/camera_model.h"
#include "parkslam/common/lot_constants.h"

namespace parkslam::perception {

struct TagDetectorOptions {
  double tag_size_m = kDefaultTagSize_m;  // edge of the black square
  float quad_decimate = 2.0f;             // libapriltag: detect on a decimated image
  bool refine_edges = true;
  int max_hamming = 1;        // bit errors accepted
  double max_range_m = 20.0;  // the paper discards tags at 20 m or more
  // The PnP bearing must agree with the direct angle within this.
  double max_angle_disagreement_rad = 0.05;

  bool IsValid(std::string* error) const;

  // The field list, walked by the options file reader (io/options_yaml.h).
  template <typename V>
  void VisitFields(V& v) {
    v("tag_size_m", tag_size_m);
    v("quad_decimate", quad_decimate);
    v("refine_edges", refine_edges);
    v("max_hamming", max_hamming);
    v("max_range_m", max_range_m);
    v("max_angle_disagreement_rad", max_angle_disagreement_rad);
  }
};

struct DetectedTag {
  int tag_id = 0;
  // Corners p[0..3] in libapriltag's order, in the project's pixel
  // convention (0-based, (0, 0) the centre of the top-left pixel: 0.5 px
  // less than libapriltag reports).
  std::array<Eigen::Vector2d, 4> corners_px{};
  Eigen::Vector2d center_px = Eigen::Vector2d::Zero();
  int hamming = 0;
  double decision_margin = 0.0;
  // With intrinsics: the tag's pose in the camera frame (x right, y down,
  // z forward), its distance d and direct angle alpha, and the tag centre
  // on the ground plane of the camera: x = sin(alpha) d, y = cos(alpha) d.
  bool has_pose = false;
  Eigen::Isometry3d T_camera_tag = Eigen::Isometry3d::Identity();
  double distance_m = 0.0;
  double alpha_rad = 0.0;
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();
};

class TagDetector {
 public:
  explicit TagDetector(const TagDetectorOptions& options = {});
  ~TagDetector();
  TagDetector(const TagDetector&) = delete;
  TagDetector& operator=(const TagDetector&) = delete;

  // Detects tags in an 8-bit grey image. With pinhole intrinsics (no
  // distortion assumed beyond what they hold) each tag also gets its pose;
  // tags whose pose fails the direct-angle check or lies at max_range_m or
  // beyond are dropped. Throws std::invalid_argument for an image that is
  // not 8-bit grey or does not match the intrinsics' size.
  // quad_decimate > 0 detects at that decimation instead of the options'
  // (a large tag is found as well on a coarser image, for a fraction of
  // the time; its corners are refined on the full image either way).
  std::vector<DetectedTag> Detect(const cv::Mat& grey,
                                  const camera::CameraIntrinsics* intrinsics = nullptr,
                                  float quad_decimate = 0.0f) const;

 private:
  struct Impl;
  TagDetectorOptions options_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace parkslam::perception

#endif  // PARKSLAM_PERCEPTION_TAG_DETECTOR_H_
