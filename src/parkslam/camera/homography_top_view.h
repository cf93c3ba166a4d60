#ifndef PARKSLAM_CAMERA_HOMOGRAPHY_TOP_VIEW_H_
#define PARKSLAM_CAMERA_HOMOGRAPHY_TOP_VIEW_H_

// Surround-view fusion for rigs calibrated by a ground-plane homography per
// camera, as many real surround-view systems are: each fisheye image is
// undistorted (cv::fisheye model, with a scaled and shifted new camera
// matrix), mapped to the bird's-eye view by its homography, turned to its
// side of the car and placed on the canvas; overlapping corners are
// blended. The geometry follows the layout of the real sample in
// shared/data/surround-view-sample (1200 x 1600 px, 1 px = 1 cm).

#include <array>
#include <opencv2/core.hpp>
#include <string>

#include "parkslam/camera/camera_model.h"

namespace parkslam::camera {

enum class Side { kFront, kBack, kLeft, kRight };

struct HomographyCamera {
  Side side = Side::kFront;
  CameraIntrinsics intrinsics;  // fisheye
  Eigen::Vector2d scale_xy{1.0, 1.0};
  Eigen::Vector2d shift_xy{0.0, 0.0};
  Eigen::Matrix3d project_matrix = Eigen::Matrix3d::Identity();  // undistorted -> bird's-eye
};

// Canvas layout: total size, and the car's rectangle [xl, xr) x [yt, yb).
struct BirdEyeLayout {
  int width = 1200, height = 1600;
  int xl = 500, xr = 700, yt = 550, yb = 1050;
};

struct HomographyRig {
  std::array<HomographyCamera, 4> cameras;  // front, back, left, right
  BirdEyeLayout layout;
};

class HomographyTopView {
 public:
  explicit HomographyTopView(const HomographyRig& rig);
  // Images in the order front, back, left, right, each of its camera's
  // resolution (throws std::invalid_argument naming the camera otherwise).
  cv::Mat Fuse(const std::array<cv::Mat, 4>& images) const;

 private:
  HomographyRig rig_;
  std::array<cv::Mat, 4> map_xy_, map_frac_;  // per camera, fixed point
  std::array<cv::Mat, 4> weight_;             // CV_32F per camera
};

const char* ToString(Side side);

}  // namespace parkslam::camera

#endif  // PARKSLAM_CAMERA_HOMOGRAPHY_TOP_VIEW_H_
