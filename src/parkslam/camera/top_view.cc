#include "parkslam/camera/top_view.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "parkslam/common/field_checker.h"
#include "parkslam/common/random.h"

namespace parkslam::camera {
namespace {

// How each camera sees one ground point: its pixel in the stacked input and
// its weight, the closeness of the point to its optical axis plus its
// priority (radians).
struct CameraView {
  bool sees = false;
  double w = 0.0;
  cv::Point2f px = cv::Point2f(-1, -1);
};

// The camera a ground point comes from, the one blended in (if any), and
// the primary's lead over it in radians (blend when below blend_angle_rad).
struct CameraPick {
  int best = -1, second = -1;
  double gap_rad = 0.0;
};

// The optical-axis rule: the two cameras of highest weight.
CameraPick PickByAxis(const std::vector<CameraView>& views) {
  CameraPick pick;
  for (int c = 0; c < static_cast<int>(views.size()); ++c) {
    if (!views[c].sees) continue;
    if (pick.best < 0 || views[c].w > views[pick.best].w) {
      pick.second = pick.best;
      pick.best = c;
    } else if (pick.second < 0 || views[c].w > views[pick.second].w) {
      pick.second = c;
    }
  }
  if (pick.best >= 0 && pick.second >= 0) pick.gap_rad = views[pick.best].w - views[pick.second].w;
  return pick;
}

enum Role { kFront, kRear, kLeft, kRight, kRoles };

// A camera's role from its optical axis in the vehicle frame (x forward,
// y left).
Role RoleOf(const CameraConfig& camera) {
  const Eigen::Vector3d axis = camera.T_vehicle_camera.rotation().col(2);
  if (std::abs(axis.x()) >= std::abs(axis.y())) return axis.x() > 0 ? kFront : kRear;
  return axis.y() > 0 ? kLeft : kRight;
}

// The footprint-rays rule (SeamStyle::kFootprintRays). Seen from the
// footprint's front corner on the point's side, the point lies at
// phi = atan2(|y| - w/2, x - x_front) from the car's axis; the front camera
// owns phi < seam_front_angle_rad, and |phi - angle| is the distance to
// the seam. The rear likewise, mirrored. Returns best = -1 where the rule
// does not apply (inside the footprint) or the role's camera is absent or
// blind there.
CameraPick PickByRays(const Eigen::Vector2d& g, const std::vector<CameraView>& views,
                      const std::array<int, kRoles>& camera_of_role, const TopViewOptions& o) {
  const double x_front = o.footprint_length_m - o.footprint_rear_overhang_m;
  const double x_rear = -o.footprint_rear_overhang_m;
  const double dy = std::abs(g.y()) - o.footprint_width_m / 2;
  CameraPick pick;
  if (dy < 0 && g.x() >= x_rear && g.x() <= x_front) return pick;
  const Role side = g.y() > 0 ? kLeft : kRight;
  const bool front_half = g.x() > (x_front + x_rear) / 2;
  const Role end = front_half ? kFront : kRear;
  const double phi = front_half ? std::atan2(dy, g.x() - x_front) : std::atan2(dy, x_rear - g.x());
  const double seam = front_half ? o.seam_front_angle_rad : o.seam_rear_angle_rad;
  const Role role = phi < seam ? end : side;
  const Role other = phi < seam ? side : end;
  const int c = camera_of_role[role];
  if (c < 0 || !views[c].sees) return pick;
  pick.best = c;
  pick.gap_rad = std::abs(phi - seam);
  const int d = camera_of_role[other];
  if (d >= 0 && views[d].sees) pick.second = d;
  return pick;
}

}  // namespace

bool TopViewOptions::IsValid(std::string* error) const {
  FieldChecker c(error);
  c.InRange(size_px, 16, 4096, "size_px", "px");
  c.Between(extent_m, 0.5, 100.0, "extent_m", "m");
  c.Magnitude(center_x_m, 100.0, "center_x_m", "m");
  c.NonNegative(blend_angle_rad, "blend_angle_rad");
  c.Between(seam_front_angle_rad, 0.0, M_PI / 2, "seam_front_angle_rad", "rad");
  c.Between(seam_rear_angle_rad, 0.0, M_PI / 2, "seam_rear_angle_rad", "rad");
  for (const double p : camera_priority_rad) {
    c.InRange(p, -1.5, 1.5, "camera_priority_rad", "rad");
  }
  c.Positive(footprint_length_m, "footprint_length_m");
  c.Positive(footprint_width_m, "footprint_width_m");
  c.NonNegative(footprint_rear_overhang_m, "footprint_rear_overhang_m");
  return c.ok();
}

Eigen::Vector2d TopViewFusion::PixelToVehicle(const Eigen::Vector2d& pixel) const {
  const double half = (options_.size_px - 1) / 2.0;
  const double m_per_px = options_.extent_m / options_.size_px;
  return {options_.center_x_m + (half - pixel.y()) * m_per_px, (half - pixel.x()) * m_per_px};
}

Eigen::Vector2d TopViewFusion::VehicleToPixel(const Eigen::Vector2d& p) const {
  const double half = (options_.size_px - 1) / 2.0;
  const double px_per_m = options_.size_px / options_.extent_m;
  return {half - p.y() * px_per_m, half - (p.x() - options_.center_x_m) * px_per_m};
}

TopViewFusion::TopViewFusion(const CameraRig& rig, const std::vector<std::string>& names,
                             const TopViewOptions& options)
    : options_(options), names_(names) {
  std::string error;
  if (!options_.IsValid(&error)) throw std::invalid_argument("top view: " + error);
  if (names_.empty()) throw std::invalid_argument("top view: no camera given");
  if (!options_.camera_priority_rad.empty() &&
      options_.camera_priority_rad.size() != names_.size()) {
    throw std::invalid_argument("top view: camera_priority_rad needs one value per camera");
  }
  std::vector<const CameraConfig*> cameras;
  std::vector<CameraModel> models;
  std::vector<int> offsets;  // row offset of each camera in the stacked input
  for (const std::string& name : names_) {
    const CameraConfig* c = rig.Find(name);
    if (c == nullptr) throw std::invalid_argument("top view: the rig has no camera '" + name + "'");
    cameras.push_back(c);
    models.emplace_back(c->intrinsics);
    sizes_.emplace_back(c->intrinsics.width, c->intrinsics.height);
    offsets.push_back(stacked_height_);
    row_offsets_.push_back(stacked_height_);
    stacked_height_ += c->intrinsics.height;
    stacked_width_ = std::max(stacked_width_, c->intrinsics.width);
  }

  const int n = options_.size_px;
  cv::Mat primary(n, n, CV_32FC2, cv::Scalar(-1, -1)),
      secondary(n, n, CV_32FC2, cv::Scalar(-1, -1));
  primary_weight_ = cv::Mat(n, n, CV_16U, cv::Scalar(0));
  valid_ = cv::Mat(n, n, CV_8U, cv::Scalar(0));
  primary_camera_ = cv::Mat(n, n, CV_8S, cv::Scalar(-1));
  secondary_camera_ = cv::Mat(n, n, CV_8S, cv::Scalar(-1));
  const double x_front = options_.footprint_length_m - options_.footprint_rear_overhang_m;
  const std::vector<double>& priority = options_.camera_priority_rad;
  std::array<int, kRoles> camera_of_role;
  camera_of_role.fill(-1);
  for (size_t c = 0; c < cameras.size(); ++c) {
    int& slot = camera_of_role[RoleOf(*cameras[c])];
    if (slot < 0) slot = static_cast<int>(c);
  }
  std::vector<CameraView> views;
  for (int v = 0; v < n; ++v) {
    for (int u = 0; u < n; ++u) {
      const Eigen::Vector2d g = PixelToVehicle({u, v});
      if (options_.mask_footprint && g.x() > -options_.footprint_rear_overhang_m &&
          g.x() < x_front && std::abs(g.y()) < options_.footprint_width_m / 2) {
        continue;
      }
      views.assign(cameras.size(), CameraView{});
      for (size_t c = 0; c < cameras.size(); ++c) {
        const Eigen::Vector3d p_camera =
            cameras[c]->T_vehicle_camera.inverse() * Eigen::Vector3d(g.x(), g.y(), 0.0);
        const auto pixel = models[c].Project(p_camera);
        if (!pixel) continue;
        const double angle = std::acos(std::clamp(p_camera.normalized().z(), -1.0, 1.0));
        views[c] = {true, -angle + (priority.empty() ? 0.0 : priority[c]),
                    cv::Point2f(static_cast<float>(pixel->x()),
                                static_cast<float>(pixel->y() + offsets[c]))};
      }
      CameraPick pick;
      if (options_.seam_style == SeamStyle::kFootprintRays) {
        pick = PickByRays(g, views, camera_of_role, options_);
      }
      if (pick.best < 0) pick = PickByAxis(views);
      if (pick.best < 0) continue;
      valid_.at<uint8_t>(v, u) = 255;
      primary_camera_.at<int8_t>(v, u) = static_cast<int8_t>(pick.best);
      primary.at<cv::Point2f>(v, u) = views[pick.best].px;
      // Feather: the second camera takes up to half where the primary leads
      // it by less than blend_angle.
      double alpha = 1.0;
      if (pick.second >= 0 && options_.blend_angle_rad > 0) {
        alpha = 0.5 + 0.5 * std::min(1.0, pick.gap_rad / options_.blend_angle_rad);
        secondary.at<cv::Point2f>(v, u) = views[pick.second].px;
        secondary_camera_.at<int8_t>(v, u) = static_cast<int8_t>(pick.second);
      } else {
        secondary.at<cv::Point2f>(v, u) = views[pick.best].px;
      }
      primary_weight_.at<uint16_t>(v, u) = static_cast<uint16_t>(std::lround(alpha * 256));
    }
  }
  cv::convertMaps(primary, cv::noArray(), primary_xy_, primary_frac_, CV_16SC2);
  cv::convertMaps(secondary, cv::noArray(), secondary_xy_, secondary_frac_, CV_16SC2);
}

namespace {

// A fixed-point map (cv::convertMaps: integer part, and the fraction as
// y * 32 + x in 32ths) rounded to the nearest pixel, kept inside the rows
// [first_row, first_row + rows) of the camera it reads (`camera` -1: the
// pixel reads nothing and keeps its place).
cv::Mat RoundedMap(const cv::Mat& xy, const cv::Mat& frac, const cv::Mat& camera,
                   const std::vector<int>& first_row, const std::vector<cv::Size>& sizes) {
  constexpr int kTab = cv::INTER_TAB_SIZE;  // 32 steps a pixel
  cv::Mat out = xy.clone();
  for (int v = 0; v < out.rows; ++v) {
    cv::Vec2s* o = out.ptr<cv::Vec2s>(v);
    const uint16_t* f = frac.ptr<uint16_t>(v);
    const int8_t* c = camera.ptr<int8_t>(v);
    for (int u = 0; u < out.cols; ++u) {
      if (c[u] < 0) continue;
      const cv::Size& size = sizes[static_cast<size_t>(c[u])];
      const int top = first_row[static_cast<size_t>(c[u])];
      const int x = o[u][0] + ((f[u] % kTab) >= kTab / 2 ? 1 : 0);
      const int y = o[u][1] + ((f[u] / kTab) >= kTab / 2 ? 1 : 0);
      o[u][0] = static_cast<short>(std::clamp(x, 0, size.width - 1));
      o[u][1] = static_cast<short>(std::clamp(y, top, top + size.height - 1));
    }
  }
  return out;
}

}  // namespace

cv::Mat TopViewFusion::Fuse(const std::vector<cv::Mat>& images, FusionLookup lookup) const {
  if (images.size() != names_.size()) {
    throw std::invalid_argument("top view: expected " + std::to_string(names_.size()) +
                                " images, got " + std::to_string(images.size()));
  }
  const int type = images.front().type();
  if (type != CV_8UC1 && type != CV_8UC3) {
    throw std::invalid_argument("top view: camera '" + names_[0] +
                                "': expected an 8-bit grey or BGR image");
  }
  cv::Mat stacked(stacked_height_, stacked_width_, type, cv::Scalar::all(0));
  int row = 0;
  for (size_t c = 0; c < images.size(); ++c) {
    if (images[c].size() != sizes_[c] || images[c].type() != type) {
      throw std::invalid_argument(
          "top view: camera '" + names_[c] + "': expected a " + std::to_string(sizes_[c].width) +
          "x" + std::to_string(sizes_[c].height) + " image like the others, got " +
          std::to_string(images[c].cols) + "x" + std::to_string(images[c].rows));
    }
    images[c].copyTo(stacked(cv::Rect(0, row, sizes_[c].width, sizes_[c].height)));
    row += sizes_[c].height;
  }
  cv::Mat a, b;
  if (lookup == FusionLookup::kNearest) {
    // Where the primary camera is alone the secondary map repeats it.
    cv::Mat secondary_camera = secondary_camera_.clone();
    primary_camera_.copyTo(secondary_camera, secondary_camera_ < 0);
    cv::remap(stacked, a,
              RoundedMap(primary_xy_, primary_frac_, primary_camera_, row_offsets_, sizes_),
              cv::noArray(), cv::INTER_NEAREST, cv::BORDER_CONSTANT);
    cv::remap(stacked, b,
              RoundedMap(secondary_xy_, secondary_frac_, secondary_camera, row_offsets_, sizes_),
              cv::noArray(), cv::INTER_NEAREST, cv::BORDER_CONSTANT);
  } else {
    cv::remap(stacked, a, primary_xy_, primary_frac_, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
    cv::remap(stacked, b, secondary_xy_, secondary_frac_, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
  }
  // out = (w a + (256 - w) b) / 256, zero where nothing is seen.
  cv::Mat out(a.size(), a.type());
  const int channels = a.channels();
  for (int v = 0; v < out.rows; ++v) {
    const uint8_t* pa = a.ptr<uint8_t>(v);
    const uint8_t* pb = b.ptr<uint8_t>(v);
    const uint16_t* pw = primary_weight_.ptr<uint16_t>(v);
    const uint8_t* pv = valid_.ptr<uint8_t>(v);
    uint8_t* po = out.ptr<uint8_t>(v);
    if (channels == 1) {
      // The common grey case, in a loop the compiler vectorizes.
      for (int u = 0; u < out.cols; ++u) {
        const unsigned w = pw[u];
        po[u] = static_cast<uint8_t>(((w * pa[u] + (256u - w) * pb[u] + 128u) >> 8) & pv[u]);
      }
      continue;
    }
    for (int u = 0; u < out.cols; ++u) {
      const unsigned w = pw[u];
      for (int k = 0; k < channels; ++k) {
        const int i = u * channels + k;
        po[i] = static_cast<uint8_t>(((w * pa[i] + (256u - w) * pb[i] + 128u) >> 8) & pv[u]);
      }
    }
  }
  return out;
}

int TopViewFusion::PrimaryCamera(int u, int v) const {
  if (u < 0 || v < 0 || u >= primary_camera_.cols || v >= primary_camera_.rows) return -1;
  return primary_camera_.at<int8_t>(v, u);
}

double TopViewFusion::PrimaryWeight(int u, int v) const {
  if (u < 0 || v < 0 || u >= primary_weight_.cols || v >= primary_weight_.rows) return 1.0;
  return primary_weight_.at<uint16_t>(v, u) / 256.0;
}

int TopViewFusion::SecondaryCamera(int u, int v) const {
  if (u < 0 || v < 0 || u >= secondary_camera_.cols || v >= secondary_camera_.rows) return -1;
  return secondary_camera_.at<int8_t>(v, u);
}

CameraRig PerturbExtrinsics(const CameraRig& rig, double rotation_sigma_rad,
                            double translation_sigma_m, std::uint64_t seed) {
  Random rng(seed);
  CameraRig out = rig;
  for (CameraConfig& c : out.cameras) {
    const Eigen::Matrix3d R =
        (Eigen::AngleAxisd(rng.Gaussian(rotation_sigma_rad), Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(rng.Gaussian(rotation_sigma_rad), Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(rng.Gaussian(rotation_sigma_rad), Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
    c.T_vehicle_camera.linear() = R * c.T_vehicle_camera.linear();
    c.T_vehicle_camera.translation() +=
        Eigen::Vector3d(rng.Gaussian(translation_sigma_m), rng.Gaussian(translation_sigma_m),
                        rng.Gaussian(translation_sigma_m));
  }
  return out;
}

}  // namespace parkslam::camera
