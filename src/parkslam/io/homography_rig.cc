#include "parkslam/io/homography_rig.h"

#include <yaml-cpp/yaml.h>
#include <Eigen/Core>
#include <Eigen/LU>

#include <cmath>
#include <cstdio>
#include <string>
#include <system_error>

#include "parkslam/common/plausible_ranges.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/io_error.h"
#include "parkslam/io/text_util.h"
#include "parkslam/io/yaml_util.h"

namespace parkslam::io {
namespace {

using yaml_util::YamlReader;

// A matrix as OpenCV's FileStorage writes it:
//   key: !!opencv-matrix {rows: R, cols: C, dt: d|f|i, data: [R x C numbers]}
// read row by row.
Eigen::MatrixXd ReadMatrix(const YAML::Node& root, const YamlReader& r, const char* key, int rows,
                           int cols) {
  const YAML::Node node = root[key];
  if (!node) r.Fail(root, key, "missing");
  r.ExpectKeys(node, key, {"rows", "cols", "dt", "data"});
  const std::string path(key);
  if (r.Int(node["rows"], path + ".rows") *
          static_cast<long long>(r.Int(node["cols"], path + ".cols")) !=
      static_cast<long long>(rows) * cols) {
    r.Fail(node, path,
           "expected a " + std::to_string(rows) + "x" + std::to_string(cols) + " matrix");
  }
  const std::string dt = r.String(node["dt"], path + ".dt");
  if (dt != "d" && dt != "f" && dt != "i") r.Fail(node["dt"], path + ".dt", "expected d, f or i");
  const YAML::Node data = node["data"];
  r.ExpectSequence(data, path + ".data");
  if (data.size() != static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols)) {
    r.Fail(
        data, path + ".data",
        "expected " + std::to_string(rows * cols) + " numbers, got " + std::to_string(data.size()));
  }
  Eigen::MatrixXd m(rows, cols);
  for (int i = 0; i < rows * cols; ++i) {
    m(i / cols, i % cols) =
        r.Double(data[static_cast<std::size_t>(i)], yaml_util::IndexKey(path + ".data", i));
  }
  return m;
}

// An OpenCV YAML file as YAML. OpenCV's own parser is not used on these
// files: it can loop for ever or allocate what a corrupt header asks (found
// by fuzz_homography_rig). Its "%YAML:1.0" line is not YAML 1.2; it becomes
// a comment, which keeps the line numbers.
YAML::Node LoadOpenCvYaml(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) ThrowIoError(file, 0, "", "no such file");
  std::string text = ReadTextFile(path, kMaxYamlBytes);
  if (text.rfind("%YAML:", 0) != 0) {
    ThrowIoError(file, 1, "", "not an OpenCV YAML file (expected the first line %YAML:1.0)");
  }
  text[0] = '#';
  return yaml_util::LoadYaml(text, file);
}

// A camera file's matrices, as read.
struct CameraMatrices {
  Eigen::MatrixXd K, D, resolution, H, scale, shift;
};

// Fails on the first value beyond the limits of common/plausible_ranges.h,
// each named by its matrix element as the file holds it (row by row).
void CheckPlausible(const YAML::Node& root, const YamlReader& r, const CameraMatrices& m) {
  const auto check = [&](const char* key, int index, double value, double min, double max,
                         const char* unit) {
    if (!(value >= min && value <= max)) {
      r.Fail(root[key]["data"][static_cast<std::size_t>(index)],
             yaml_util::IndexKey(std::string(key) + ".data", static_cast<std::size_t>(index)),
             text::OutsidePlausible(value, min, max, unit));
    }
  };
  const Eigen::MatrixXd& K = m.K;
  for (int i = 0; i < 2; ++i) {
    check("resolution", i, m.resolution(i, 0), kMinImageSide_px, kMaxImageSide_px, "px");
  }
  const auto width = static_cast<int>(m.resolution(0, 0));
  const auto height = static_cast<int>(m.resolution(1, 0));
  if (static_cast<long long>(width) * height > kMaxImagePixels) {
    r.Fail(root["resolution"], "resolution",
           std::to_string(width) + " x " + std::to_string(height) +
               " pixels, beyond the plausible " + std::to_string(kMaxImagePixels));
  }
  check("camera_matrix", 0, K(0, 0), kMinFocalLength_px, kMaxFocalLength_px, "px");
  check("camera_matrix", 4, K(1, 1), kMinFocalLength_px, kMaxFocalLength_px, "px");
  check("camera_matrix", 2, K(0, 2), -kPrincipalPointMargin * width,
        (1.0 + kPrincipalPointMargin) * width, "px");
  check("camera_matrix", 5, K(1, 2), -kPrincipalPointMargin * height,
        (1.0 + kPrincipalPointMargin) * height, "px");
  for (int i = 0; i < 4; ++i) {
    check("dist_coeffs", i, m.D(i, 0), -kMaxDistortionCoefficient, kMaxDistortionCoefficient, "");
  }
  // Singular, the homography maps the undistorted image onto a line or a
  // point: an all-zero or rank-deficient matrix is no calibration. The
  // ratio does not change when H is scaled, as a homography may be.
  const double norm = m.H.norm();
  const double ratio = norm > 0.0 ? std::abs(m.H.determinant()) / (norm * norm * norm) : 0.0;
  if (!(ratio >= kMinHomographyDeterminant)) {
    char what[160];
    std::snprintf(what, sizeof what,
                  "singular: |det| / |H|^3 is %.3g, below the plausible %.3g (it maps the "
                  "image onto a line)",
                  ratio, kMinHomographyDeterminant);
    r.Fail(root["project_matrix"], "project_matrix", what);
  }
  for (int i = 0; i < 2; ++i) {
    check("scale_xy", i, m.scale(i, 0), kMinUndistortScale, kMaxUndistortScale, "");
    check("shift_xy", i, m.shift(i, 0), -kMaxImageSide_px, kMaxImageSide_px, "px");
  }
}

camera::HomographyCamera LoadCamera(const std::filesystem::path& path, camera::Side side) {
  const std::string file = path.string();
  const YAML::Node root = LoadOpenCvYaml(path);
  const YamlReader r(file, true);
  r.ExpectMap(root, "");
  r.CheckKeys(
      root, "",
      {"camera_matrix", "dist_coeffs", "resolution", "project_matrix", "scale_xy", "shift_xy"});
  CameraMatrices m;
  m.K = ReadMatrix(root, r, "camera_matrix", 3, 3);
  m.D = ReadMatrix(root, r, "dist_coeffs", 4, 1);
  m.resolution = ReadMatrix(root, r, "resolution", 2, 1);
  m.H = ReadMatrix(root, r, "project_matrix", 3, 3);
  m.scale = ReadMatrix(root, r, "scale_xy", 2, 1);
  m.shift = ReadMatrix(root, r, "shift_xy", 2, 1);
  CheckPlausible(root, r, m);
  const Eigen::MatrixXd& K = m.K;
  camera::HomographyCamera cam;
  cam.side = side;
  cam.intrinsics.kind = camera::CameraKind::kFisheye;
  cam.intrinsics.width = static_cast<int>(m.resolution(0, 0));
  cam.intrinsics.height = static_cast<int>(m.resolution(1, 0));
  cam.intrinsics.fx = K(0, 0);
  cam.intrinsics.fy = K(1, 1);
  cam.intrinsics.cx = K(0, 2);
  cam.intrinsics.cy = K(1, 2);
  for (int i = 0; i < 4; ++i) cam.intrinsics.distortion[i] = m.D(i, 0);
  cam.scale_xy = {m.scale(0, 0), m.scale(1, 0)};
  cam.shift_xy = {m.shift(0, 0), m.shift(1, 0)};
  cam.project_matrix = m.H;
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
