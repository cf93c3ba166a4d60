#include "parkslam/camera/top_view.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "parkslam/common/field_checker.h"
#include "parkslam/common/random.h"

namespace parkslam::camera {
namespace {

// The two cameras that see a ground point best, by closeness to their axis
// plus their priority, with the point's pixel in the stacked input.
struct CameraPick {
  double best_w = 0.0, second_w = 0.0;
  bool has_best = false, has_second = false;
  cv::Point2f best_px = cv::Point2f(-1, -1), second_px = cv::Point2f(-1, -1);
  int best_camera = -1, second_camera = -1;
};

CameraPick PickCameras(const Eigen::Vector2d& g, const std::vector<const CameraConfig*>& cameras,
                       const std::vector<CameraModel>& models, const std::vector<int>& offsets,
                       const std::vector<double>& camera_priority_rad) {
  CameraPick pick;
  for (size_t c = 0; c < cameras.size(); ++c) {
    const Eigen::Vector3d p_camera =
        cameras[c]->T_vehicle_camera.inverse() * Eigen::Vector3d(g.x(), g.y(), 0.0);
    const auto pixel = models[c].Project(p_camera);
    if (!pixel) continue;
    const double angle = std::acos(std::clamp(p_camera.normalized().z(), -1.0, 1.0));
    const double w = -angle + (camera_priority_rad.empty() ? 0.0 : camera_priority_rad[c]);
    const cv::Point2f stacked(static_cast<float>(pixel->x()),
                              static_cast<float>(pixel->y() + offsets[c]));
    if (!pick.has_best || w > pick.best_w) {
      pick.second_w = pick.best_w;
      pick.second_px = pick.best_px;
      pick.second_camera = pick.best_camera;
      pick.has_second = pick.has_best;
      pick.best_w = w;
      pick.best_px = stacked;
      pick.has_best = true;
      pick.best_camera = static_cast<int>(c);
    } else if (!pick.has_second || w > pick.second_w) {
      pick.second_w = w;
      pick.second_px = stacked;
      pick.second_camera = static_cast<int>(c);
      pick.has_second = true;
    }
  }
  return pick;
}

}  // namespace

bool TopViewOptions::IsValid(std::string* error) const {
  FieldChecker c(error);
  c.InRange(size_px, 16, 4096, "size_px", "px");
  c.Between(extent_m, 0.5, 100.0, "extent_m", "m");
  c.Magnitude(center_x_m, 100.0, "center_x_m", "m");
  c.NonNegative(blend_angle_rad, "blend_angle_rad");
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
  for (int v = 0; v < n; ++v) {
    for (int u = 0; u < n; ++u) {
      const Eigen::Vector2d g = PixelToVehicle({u, v});
      if (options_.mask_footprint && g.x() > -options_.footprint_rear_overhang_m &&
          g.x() < x_front && std::abs(g.y()) < options_.footprint_width_m / 2) {
        continue;
      }
      const CameraPick pick =
          PickCameras(g, cameras, models, offsets, options_.camera_priority_rad);
      if (!pick.has_best) continue;
      valid_.at<uint8_t>(v, u) = 255;
      primary_camera_.at<int8_t>(v, u) = static_cast<int8_t>(pick.best_camera);
      primary.at<cv::Point2f>(v, u) = pick.best_px;
      // Feather: the second camera takes up to half where the two are
      // within blend_angle of each other.
      double alpha = 1.0;
      if (pick.has_second && options_.blend_angle_rad > 0) {
        const double gap = pick.best_w - pick.second_w;  // >= 0, radians
        alpha = 0.5 + 0.5 * std::min(1.0, gap / options_.blend_angle_rad);
        secondary.at<cv::Point2f>(v, u) = pick.second_px;
        secondary_camera_.at<int8_t>(v, u) = static_cast<int8_t>(pick.second_camera);
      } else {
        secondary.at<cv::Point2f>(v, u) = pick.best_px;
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
