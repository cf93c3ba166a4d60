#include "parkslam/camera/homography_top_view.h"

#include <opencv2/imgproc.hpp>

#include <Eigen/LU>
#include <cmath>
#include <stdexcept>

namespace parkslam::camera {
namespace {

// Pixel of the camera's own projected (bird's-eye) image seen at canvas
// pixel (x, y): each side's projected image is turned to face outwards.
Eigen::Vector2d ProjectedPixel(Side side, const BirdEyeLayout& l, double x, double y) {
  switch (side) {
    case Side::kFront:
      return {x, y};
    case Side::kBack:
      return {l.width - 1 - x, l.yt - 1 - (y - l.yb)};
    case Side::kLeft:
      return {l.height - 1 - y, x};
    case Side::kRight:
      return {y, l.xl - 1 - (x - l.xr)};
  }
  return {x, y};
}

bool InSide(Side side, const BirdEyeLayout& l, int x, int y) {
  switch (side) {
    case Side::kFront:
      return y < l.yt;
    case Side::kBack:
      return y >= l.yb;
    case Side::kLeft:
      return x < l.xl;
    case Side::kRight:
      return x >= l.xr;
  }
  return false;
}

}  // namespace

const char* ToString(Side side) {
  switch (side) {
    case Side::kFront:
      return "front";
    case Side::kBack:
      return "back";
    case Side::kLeft:
      return "left";
    case Side::kRight:
      return "right";
  }
  return "front";
}

HomographyTopView::HomographyTopView(const HomographyRig& rig) : rig_(rig) {
  const BirdEyeLayout& l = rig_.layout;
  for (int c = 0; c < 4; ++c) {
    const HomographyCamera& cam = rig_.cameras[c];
    const CameraModel model(cam.intrinsics);
    // The new camera matrix of the undistortion: focal lengths scaled,
    // principal point shifted.
    const double fx = cam.intrinsics.fx * cam.scale_xy.x(),
                 fy = cam.intrinsics.fy * cam.scale_xy.y();
    const double cx = cam.intrinsics.cx + cam.shift_xy.x(),
                 cy = cam.intrinsics.cy + cam.shift_xy.y();
    const Eigen::Matrix3d H_inv = cam.project_matrix.inverse();
    cv::Mat map(l.height, l.width, CV_32FC2, cv::Scalar(-1, -1));
    weight_[c] = cv::Mat(l.height, l.width, CV_32F, cv::Scalar(0));
    for (int y = 0; y < l.height; ++y) {
      for (int x = 0; x < l.width; ++x) {
        if (!InSide(cam.side, l, x, y)) continue;
        const bool in_car = x >= l.xl && x < l.xr && y >= l.yt && y < l.yb;
        if (in_car) continue;
        const Eigen::Vector2d p = ProjectedPixel(cam.side, l, x, y);
        const Eigen::Vector3d u = H_inv * Eigen::Vector3d(p.x(), p.y(), 1.0);
        if (std::abs(u.z()) < 1e-12) continue;  // a homography's scale sign is arbitrary
        const Eigen::Vector3d ray((u.x() / u.z() - cx) / fx, (u.y() / u.z() - cy) / fy, 1.0);
        const auto src = model.Project(ray);
        if (!src) continue;
        map.at<cv::Point2f>(y, x) =
            cv::Point2f(static_cast<float>(src->x()), static_cast<float>(src->y()));
        weight_[c].at<float>(y, x) = 1.0f;
      }
    }
    cv::convertMaps(map, cv::noArray(), map_xy_[c], map_frac_[c], CV_16SC2);
  }
  // Overlapping corners: a linear ramp across each corner square, from the
  // front/back camera at its outer edge to the side camera at the other.
  for (int y = 0; y < l.height; ++y) {
    for (int x = 0; x < l.width; ++x) {
      const bool top = y < l.yt, bottom = y >= l.yb, left = x < l.xl, right = x >= l.xr;
      if (!((top || bottom) && (left || right))) continue;
      // 0 at the outer corner's diagonal toward the car: share by angle.
      const double dx = left ? (l.xl - x) / static_cast<double>(l.xl)
                             : (x - l.xr + 1) / static_cast<double>(l.width - l.xr);
      const double dy = top ? (l.yt - y) / static_cast<double>(l.yt)
                            : (y - l.yb + 1) / static_cast<double>(l.height - l.yb);
      const double w_side = dx / (dx + dy + 1e-12);  // far out sideways: the side camera
      const int fb = top ? 0 : 1, lr = left ? 2 : 3;
      const bool fb_ok = weight_[fb].at<float>(y, x) > 0, lr_ok = weight_[lr].at<float>(y, x) > 0;
      if (fb_ok && lr_ok) {
        weight_[fb].at<float>(y, x) = static_cast<float>(1.0 - w_side);
        weight_[lr].at<float>(y, x) = static_cast<float>(w_side);
      }
    }
  }
}

cv::Mat HomographyTopView::Fuse(const std::array<cv::Mat, 4>& images) const {
  const BirdEyeLayout& l = rig_.layout;
  cv::Mat sum(l.height, l.width, CV_32FC3, cv::Scalar::all(0));
  for (int c = 0; c < 4; ++c) {
    const CameraIntrinsics& in = rig_.cameras[c].intrinsics;
    if (images[c].cols != in.width || images[c].rows != in.height || images[c].type() != CV_8UC3) {
      throw std::invalid_argument(std::string("bird's-eye view: camera '") +
                                  ToString(rig_.cameras[c].side) + "': expected a " +
                                  std::to_string(in.width) + "x" + std::to_string(in.height) +
                                  " colour image, got " + std::to_string(images[c].cols) + "x" +
                                  std::to_string(images[c].rows));
    }
    cv::Mat warped, warped_f, weight3;
    cv::remap(images[c], warped, map_xy_[c], map_frac_[c], cv::INTER_LINEAR, cv::BORDER_CONSTANT);
    warped.convertTo(warped_f, CV_32FC3);
    cv::Mat channels[] = {weight_[c], weight_[c], weight_[c]};
    cv::merge(channels, 3, weight3);
    sum += warped_f.mul(weight3);
  }
  cv::Mat out;
  sum.convertTo(out, CV_8UC3);
  return out;
}

}  // namespace parkslam::camera
