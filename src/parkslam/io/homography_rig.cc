#include "parkslam/io/homography_rig.h"

#include <opencv2/core.hpp>

#include <cmath>

#include "parkslam/io/io_error.h"

namespace parkslam::io {
namespace {

cv::Mat ReadMatrix(const cv::FileStorage& fs, const std::string& file, const char* key, int rows,
                   int cols) {
  cv::Mat m;
  try {
    fs[key] >> m;
  } catch (const cv::Exception&) {
    m.release();
  }
  if (m.empty() || m.rows * m.cols != rows * cols) {
    ThrowIoError(file, 0, key, "expected a " + std::to_string(rows) + "x" + std::to_string(cols) +
                                   " matrix");
  }
  m.convertTo(m, CV_64F);
  m = m.reshape(1, rows);
  for (int r = 0; r < m.rows; ++r) {
    for (int c = 0; c < m.cols; ++c) {
      if (!std::isfinite(m.at<double>(r, c))) ThrowIoError(file, 0, key, "not a finite number");
    }
  }
  return m;
}

camera::HomographyCamera LoadCamera(const std::filesystem::path& path, camera::Side side) {
  const std::string file = path.string();
  if (!std::filesystem::exists(path)) ThrowIoError(file, 0, "", "no such file");
  cv::FileStorage fs;
  try {
    fs.open(file, cv::FileStorage::READ);
  } catch (const cv::Exception& e) {
    ThrowIoError(file, 0, "", std::string("not a readable OpenCV YAML file: ") + e.what());
  }
  if (!fs.isOpened()) ThrowIoError(file, 0, "", "not a readable OpenCV YAML file");
  const cv::Mat K = ReadMatrix(fs, file, "camera_matrix", 3, 3);
  const cv::Mat D = ReadMatrix(fs, file, "dist_coeffs", 4, 1);
  const cv::Mat resolution = ReadMatrix(fs, file, "resolution", 2, 1);
  const cv::Mat H = ReadMatrix(fs, file, "project_matrix", 3, 3);
  const cv::Mat scale = ReadMatrix(fs, file, "scale_xy", 2, 1);
  const cv::Mat shift = ReadMatrix(fs, file, "shift_xy", 2, 1);
  camera::HomographyCamera cam;
  cam.side = side;
  cam.intrinsics.kind = camera::CameraKind::kFisheye;
  cam.intrinsics.width = static_cast<int>(resolution.at<double>(0, 0));
  cam.intrinsics.height = static_cast<int>(resolution.at<double>(1, 0));
  if (cam.intrinsics.width < 16 || cam.intrinsics.height < 16) {
    ThrowIoError(file, 0, "resolution", "must be at least 16x16");
  }
  cam.intrinsics.fx = K.at<double>(0, 0);
  cam.intrinsics.fy = K.at<double>(1, 1);
  cam.intrinsics.cx = K.at<double>(0, 2);
  cam.intrinsics.cy = K.at<double>(1, 2);
  if (!(cam.intrinsics.fx > 0 && cam.intrinsics.fy > 0)) {
    ThrowIoError(file, 0, "camera_matrix", "focal lengths must be positive");
  }
  for (int i = 0; i < 4; ++i) cam.intrinsics.distortion[i] = D.at<double>(i, 0);
  cam.scale_xy = {scale.at<double>(0, 0), scale.at<double>(1, 0)};
  cam.shift_xy = {shift.at<double>(0, 0), shift.at<double>(1, 0)};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) cam.project_matrix(r, c) = H.at<double>(r, c);
  }
  return cam;
}

}  // namespace

camera::HomographyRig LoadHomographyRig(const std::filesystem::path& folder) {
  camera::HomographyRig rig;
  const camera::Side sides[] = {camera::Side::kFront, camera::Side::kBack, camera::Side::kLeft,
                                camera::Side::kRight};
  for (int c = 0; c < 4; ++c) {
    rig.cameras[c] =
        LoadCamera(folder / (std::string(camera::ToString(sides[c])) + ".yaml"), sides[c]);
  }
  return rig;
}

}  // namespace parkslam::io
