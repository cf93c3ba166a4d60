#include "parkslam/perception/tag_detector.h"

#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <stdexcept>

#include "parkslam/common/field_checker.h"

namespace parkslam::perception {

bool TagDetectorOptions::IsValid(std::string* error) const {
  FieldChecker c(error);
  c.Positive(tag_size_m, "tag_size_m");
  c.AtLeast(quad_decimate, 1.0, "quad_decimate");
  c.InRange(max_hamming, 0, 3, "max_hamming", "");
  c.Positive(max_range_m, "max_range_m");
  c.Positive(max_angle_disagreement_rad, "max_angle_disagreement_rad");
  return c.ok();
}

struct TagDetector::Impl {
  apriltag_family_t* family = nullptr;
  apriltag_detector_t* detector = nullptr;
  ~Impl() {
    if (detector != nullptr) apriltag_detector_destroy(detector);
    if (family != nullptr) tag36h11_destroy(family);
  }
};

TagDetector::TagDetector(const TagDetectorOptions& options)
    : options_(options), impl_(std::make_unique<Impl>()) {
  std::string error;
  if (!options_.IsValid(&error)) throw std::invalid_argument("tag detector: " + error);
  impl_->family = tag36h11_create();
  impl_->detector = apriltag_detector_create();
  apriltag_detector_add_family_bits(impl_->detector, impl_->family, options_.max_hamming);
  impl_->detector->quad_decimate = options_.quad_decimate;
  impl_->detector->refine_edges = options_.refine_edges;
  impl_->detector->nthreads = 1;
}

TagDetector::~TagDetector() = default;

std::vector<DetectedTag> TagDetector::Detect(const cv::Mat& grey,
                                             const camera::CameraIntrinsics* intrinsics,
                                             float quad_decimate) const {
  if (grey.type() != CV_8UC1)
    throw std::invalid_argument("tag detector: expected an 8-bit grey image");
  if (intrinsics != nullptr &&
      (grey.cols != intrinsics->width || grey.rows != intrinsics->height)) {
    throw std::invalid_argument("tag detector: image is " + std::to_string(grey.cols) + "x" +
                                std::to_string(grey.rows) + ", the camera " +
                                std::to_string(intrinsics->width) + "x" +
                                std::to_string(intrinsics->height));
  }
  cv::Mat contiguous = grey.isContinuous() ? grey : grey.clone();
  image_u8_t image{contiguous.cols, contiguous.rows, static_cast<int32_t>(contiguous.step),
                   contiguous.data};
  impl_->detector->quad_decimate = quad_decimate > 0.0f ? quad_decimate : options_.quad_decimate;
  zarray_t* detections = apriltag_detector_detect(impl_->detector, &image);
  std::vector<DetectedTag> tags;
  for (int i = 0; i < zarray_size(detections); ++i) {
    apriltag_detection_t* d = nullptr;
    zarray_get(detections, i, &d);
    DetectedTag tag;
    tag.tag_id = d->id;
    tag.hamming = d->hamming;
    tag.decision_margin = d->decision_margin;
    for (int k = 0; k < 4; ++k) tag.corners_px[k] = {d->p[k][0] - 0.5, d->p[k][1] - 0.5};
    tag.center_px = {d->c[0] - 0.5, d->c[1] - 0.5};
    if (intrinsics == nullptr) {
      tags.push_back(tag);
      continue;
    }
    // PnP, IPPE square: object corners in libapriltag's order.
    const double h = options_.tag_size_m / 2;
    const std::vector<cv::Point3d> object{{-h, h, 0}, {h, h, 0}, {h, -h, 0}, {-h, -h, 0}};
    std::vector<cv::Point2d> image_points;
    for (const Eigen::Vector2d& c : tag.corners_px) image_points.emplace_back(c.x(), c.y());
    const cv::Matx33d K(intrinsics->fx, 0, intrinsics->cx, 0, intrinsics->fy, intrinsics->cy, 0, 0,
                        1);
    const cv::Vec4d D(intrinsics->distortion[0], intrinsics->distortion[1],
                      intrinsics->distortion[2], intrinsics->distortion[3]);
    std::vector<cv::Mat> rvecs, tvecs;
    cv::solvePnPGeneric(object, image_points, K, D, rvecs, tvecs, false, cv::SOLVEPNP_IPPE_SQUARE);
    if (tvecs.empty()) continue;
    // The direct angle of the tag centre (paper III-B).
    tag.alpha_rad = std::atan((tag.center_px.x() - intrinsics->cx) / intrinsics->fx);
    // Of the two solutions (sorted by reprojection error), the first whose
    // bearing agrees with the direct angle.
    for (size_t s = 0; s < tvecs.size(); ++s) {
      const cv::Vec3d t = tvecs[s];
      if (!(t[2] > 0.0)) continue;
      const double bearing = std::atan2(t[0], t[2]);
      if (std::abs(bearing - tag.alpha_rad) > options_.max_angle_disagreement_rad) continue;
      cv::Mat R;
      cv::Rodrigues(rvecs[s], R);
      Eigen::Matrix3d R_eigen;
      cv::cv2eigen(R, R_eigen);
      tag.T_camera_tag.linear() = R_eigen;
      tag.T_camera_tag.translation() = Eigen::Vector3d(t[0], t[1], t[2]);
      tag.distance_m = std::sqrt(t.dot(t));
      tag.position_m = {std::sin(tag.alpha_rad) * tag.distance_m,
                        std::cos(tag.alpha_rad) * tag.distance_m};
      tag.has_pose = true;
      break;
    }
    if (tag.has_pose && tag.distance_m < options_.max_range_m) tags.push_back(tag);
  }
  apriltag_detections_destroy(detections);
  return tags;
}

}  // namespace parkslam::perception
