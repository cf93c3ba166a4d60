#include "parkslam/io/rig_yaml.h"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <set>

#include "parkslam/common/plausible_ranges.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/io_error.h"
#include "parkslam/io/text_util.h"
#include "parkslam/io/yaml_util.h"

namespace parkslam::io {
namespace {

using yaml_util::IndexKey;
using yaml_util::JoinKey;
using yaml_util::YamlReader;

constexpr double kDeg = std::numbers::pi / 180.0;

// The viewing direction (yaw, pitch down) and roll of a camera, from its
// rotation: camera z is the viewing direction, camera x its right.
void Angles(const Eigen::Matrix3d& R, double* yaw, double* pitch_down, double* roll) {
  const Eigen::Vector3d forward = R.col(2);
  *yaw = std::atan2(forward.y(), forward.x());
  *pitch_down = std::asin(std::clamp(-forward.z(), -1.0, 1.0));
  const Eigen::Vector3d level_right(std::sin(*yaw), -std::cos(*yaw), 0.0);
  const Eigen::Vector3d level_down = forward.cross(level_right);
  *roll = std::atan2(R.col(0).dot(level_down), R.col(0).dot(level_right));
}

Eigen::Matrix3d Rotation(double yaw, double pitch_down, double roll) {
  const Eigen::Vector3d forward(std::cos(yaw) * std::cos(pitch_down),
                                std::sin(yaw) * std::cos(pitch_down), -std::sin(pitch_down));
  const Eigen::Vector3d level_right(std::sin(yaw), -std::cos(yaw), 0.0);
  const Eigen::Vector3d level_down = forward.cross(level_right);
  const Eigen::Vector3d right = std::cos(roll) * level_right + std::sin(roll) * level_down;
  Eigen::Matrix3d R;
  R.col(0) = right;
  R.col(1) = forward.cross(right);
  R.col(2) = forward;
  return R;
}

// The limits of common/plausible_ranges.h on what a camera entry holds.

int ImageSide(const YamlReader& r, const YAML::Node& node, const std::string& path) {
  const int side = r.Int(node, path);
  if (side < kMinImageSide_px || side > kMaxImageSide_px) {
    r.Fail(node, path, text::OutsidePlausible(side, kMinImageSide_px, kMaxImageSide_px, "px"));
  }
  return side;
}

double FocalLength(const YamlReader& r, const YAML::Node& node, const std::string& path) {
  return r.DoubleIn(node, path, kMinFocalLength_px, kMaxFocalLength_px, "px");
}

// cx or cy of an image `size` pixels wide or high.
double PrincipalPoint(const YamlReader& r, const YAML::Node& node, const std::string& path,
                      int size) {
  return r.DoubleIn(node, path, -kPrincipalPointMargin * size, (1.0 + kPrincipalPointMargin) * size,
                    "px");
}

// Above the ground the cameras look at (a top view from a camera at or below
// it is empty), below any ceiling.
double CameraHeight(const YamlReader& r, const YAML::Node& node, const std::string& path) {
  const double z_m = r.Double(node, path);
  if (!(z_m > 0.0)) {
    std::string value;
    text::AppendDouble(&value, z_m);
    r.Fail(node, path, value + " puts the camera on or under the ground (z is up)");
  }
  if (z_m > kMaxCameraHeight_m) {
    r.Fail(node, path, text::BeyondPlausible(z_m, kMaxCameraHeight_m, "m"));
  }
  return z_m;
}

}  // namespace

camera::CameraRig RigFromYaml(const std::string& text, const std::string& source) {
  const YAML::Node root = yaml_util::LoadYaml(text, source);
  const YamlReader r(source, true);
  r.ExpectKeys(root, "", {"cameras"});
  const YAML::Node list = root["cameras"];
  r.ExpectSequence(list, "cameras");
  camera::CameraRig rig;
  std::set<std::string> names;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string path = IndexKey("cameras", i);
    const YAML::Node n = list[i];
    r.ExpectKeys(n, path,
                 {"name", "model", "width", "height", "fx", "fy", "cx", "cy", "distortion",
                  "position_m", "yaw_deg", "pitch_down_deg", "roll_deg"});
    camera::CameraConfig c;
    c.name = r.String(n["name"], JoinKey(path, "name"));
    if (c.name.empty() || !names.insert(c.name).second) {
      ThrowIoError(source, 0, JoinKey(path, "name"), "must be non-empty and unique");
    }
    const std::string model = r.String(n["model"], JoinKey(path, "model"));
    if (model != "pinhole" && model != "fisheye") {
      ThrowIoError(source, 0, JoinKey(path, "model"), "must be pinhole or fisheye");
    }
    camera::CameraIntrinsics& in = c.intrinsics;
    in.kind = model == "fisheye" ? camera::CameraKind::kFisheye : camera::CameraKind::kPinhole;
    in.width = ImageSide(r, n["width"], JoinKey(path, "width"));
    in.height = ImageSide(r, n["height"], JoinKey(path, "height"));
    const long long pixels = static_cast<long long>(in.width) * in.height;
    if (pixels > kMaxImagePixels) {
      r.Fail(n["height"], JoinKey(path, "height"),
             std::to_string(in.width) + " x " + std::to_string(in.height) + " is " +
                 std::to_string(pixels) + " pixels, beyond the plausible " +
                 std::to_string(kMaxImagePixels));
    }
    in.fx = FocalLength(r, n["fx"], JoinKey(path, "fx"));
    in.fy = FocalLength(r, n["fy"], JoinKey(path, "fy"));
    in.cx = PrincipalPoint(r, n["cx"], JoinKey(path, "cx"), in.width);
    in.cy = PrincipalPoint(r, n["cy"], JoinKey(path, "cy"), in.height);
    const YAML::Node d = n["distortion"];
    r.ExpectSequence(d, JoinKey(path, "distortion"));
    if (d.size() != 4) ThrowIoError(source, 0, JoinKey(path, "distortion"), "expected 4 numbers");
    for (int k = 0; k < 4; ++k) {
      in.distortion[k] = r.BoundedDouble(d[k], IndexKey(JoinKey(path, "distortion"), k),
                                         kMaxDistortionCoefficient, "");
    }
    const YAML::Node p = n["position_m"];
    r.ExpectSequence(p, JoinKey(path, "position_m"));
    if (p.size() != 3) ThrowIoError(source, 0, JoinKey(path, "position_m"), "expected [x, y, z]");
    Eigen::Vector3d position;
    for (int k = 0; k < 2; ++k) {
      position[k] =
          r.BoundedDouble(p[k], IndexKey(JoinKey(path, "position_m"), k), kMaxCameraOffset_m, "m");
    }
    position.z() = CameraHeight(r, p[2], IndexKey(JoinKey(path, "position_m"), 2));
    const double yaw =
        r.BoundedDouble(n["yaw_deg"], JoinKey(path, "yaw_deg"), kMaxAngle_deg, "deg");
    const double pitch =
        r.BoundedDouble(n["pitch_down_deg"], JoinKey(path, "pitch_down_deg"), kMaxAngle_deg, "deg");
    const double roll =
        r.BoundedDouble(n["roll_deg"], JoinKey(path, "roll_deg"), kMaxAngle_deg, "deg");
    c.T_vehicle_camera.linear() = Rotation(yaw * kDeg, pitch * kDeg, roll * kDeg);
    c.T_vehicle_camera.translation() = position;
    rig.cameras.push_back(c);
  }
  return rig;
}

camera::CameraRig LoadRig(const std::filesystem::path& path) {
  return RigFromYaml(ReadTextFile(path, kMaxYamlBytes), path.string());
}

std::string RigToYaml(const camera::CameraRig& rig) {
  std::string out = "# parkslam camera rig (docs/cameras.md)\ncameras:\n";
  char line[1024];
  for (const camera::CameraConfig& c : rig.cameras) {
    const camera::CameraIntrinsics& in = c.intrinsics;
    double yaw, pitch, roll;
    Angles(c.T_vehicle_camera.linear(), &yaw, &pitch, &roll);
    const Eigen::Vector3d t = c.T_vehicle_camera.translation();
    out += "  - name: " + c.name + "\n";
    std::snprintf(line, sizeof line,
                  "    model: %s\n    width: %d\n    height: %d\n"
                  "    fx: %.17g\n    fy: %.17g\n    cx: %.17g\n    cy: %.17g\n"
                  "    distortion: [%.17g, %.17g, %.17g, %.17g]\n"
                  "    position_m: [%.17g, %.17g, %.17g]\n"
                  "    yaw_deg: %.17g\n    pitch_down_deg: %.17g\n    roll_deg: %.17g\n",
                  in.kind == camera::CameraKind::kFisheye ? "fisheye" : "pinhole", in.width,
                  in.height, in.fx, in.fy, in.cx, in.cy, in.distortion[0], in.distortion[1],
                  in.distortion[2], in.distortion[3], t.x(), t.y(), t.z(), yaw / kDeg, pitch / kDeg,
                  roll / kDeg);
    out += line;
  }
  return out;
}

}  // namespace parkslam::io
