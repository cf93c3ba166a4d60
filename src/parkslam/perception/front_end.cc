#include "parkslam/perception/front_end.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <opencv2/imgproc.hpp>

#include "parkslam/camera/image_plane.h"
#include "parkslam/common/angles.h"
#include "parkslam/common/enum_names.h"
#include "parkslam/common/field_checker.h"

namespace parkslam::perception {
namespace {

using Clock = std::chrono::steady_clock;

double MsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

double Cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

const camera::CameraConfig* FindCamera(const camera::CameraRig& rig, const std::string& name) {
  for (const camera::CameraConfig& c : rig.cameras) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

}  // namespace

const char* ToString(DetectorKind kind) { return EnumName(kind); }

DetectorKind ParseDetectorKind(const std::string& text) {
  if (const std::optional<DetectorKind> kind = EnumFromName<DetectorKind>(text)) return *kind;
  throw std::invalid_argument("unknown detector '" + text + "' (expected classical or learned)");
}

std::string DefaultModelDir() { return PARKSLAM_MODEL_DIR; }

bool TagWindowOptions::IsValid(std::string* error) const {
  FieldChecker c(error);
  c.InRange(sigmas, 0.0, 10.0, "sigmas", "");
  c.InRange(margin_px, 0.0, 1000.0, "margin_px", "px");
  c.InRange(min_decimated_px, 1.0, 1000.0, "min_decimated_px", "px");
  c.InRange(max_band_share, 0.0, 1.0, "max_band_share", "");
  return c.ok();
}

PerceptionFrontEnd::PerceptionFrontEnd(const camera::CameraRig& rig,
                                       const PerceptionOptions& options)
    : options_(options) {
  for (const std::string& name : options_.fisheye_cameras) {
    if (FindCamera(rig, name) == nullptr) {
      throw std::invalid_argument("perception: the rig has no camera '" + name + "'");
    }
  }
  const camera::CameraConfig* tag_camera = FindCamera(rig, options_.tag_camera);
  if (tag_camera == nullptr || tag_camera->intrinsics.kind != camera::CameraKind::kPinhole) {
    throw std::invalid_argument("perception: the rig has no pinhole camera '" +
                                options_.tag_camera + "' for tags");
  }
  tag_camera_ = *tag_camera;
  SetTagBand();
  fusion_ =
      std::make_unique<camera::TopViewFusion>(rig, options_.fisheye_cameras, options_.top_view);
  MakeDetectors();
  MakeMasks();
}

void PerceptionFrontEnd::SetTagBand() {
  const camera::CameraIntrinsics& k = tag_camera_.intrinsics;
  const double camera_z = tag_camera_.T_vehicle_camera.translation().z();
  // The band only holds for a camera looking level and upright.
  const Eigen::Vector3d z_axis = tag_camera_.T_vehicle_camera.rotation().col(2);
  const Eigen::Vector3d y_axis = tag_camera_.T_vehicle_camera.rotation().col(1);
  int first = 0, last = k.height - 1;
  if (options_.tag_max_height_m > options_.tag_min_height_m && options_.tag_min_range_m > 0.0 &&
      std::abs(z_axis.z()) < 0.02 && y_axis.z() < -0.999) {
    const double d = options_.tag_min_range_m;
    first = static_cast<int>(std::floor(k.cy - k.fy * (options_.tag_max_height_m - camera_z) / d));
    last = static_cast<int>(std::ceil(k.cy + k.fy * (camera_z - options_.tag_min_height_m) / d));
    first = std::clamp(first, 0, k.height - 1);
    last = std::clamp(last, first, k.height - 1);
  }
  tag_first_row_ = first;
  tag_rows_ = last - first + 1;
  tag_band_intrinsics_ = k;
  tag_band_intrinsics_.height = tag_rows_;
  tag_band_intrinsics_.cy = k.cy - first;
}

void PerceptionFrontEnd::MakeDetectors() {
  // The detector's scale follows the top view.
  const double pixels_per_m = options_.top_view.size_px / options_.top_view.extent_m;
  options_.slots.pixels_per_m = pixels_per_m;
  options_.ids.pixels_per_m = pixels_per_m;
  options_.learned_slots.pairing.pixels_per_m = pixels_per_m;
  options_.learned_slots.classical_options = options_.slots;
  options_.learned_ids.pixels_per_m = pixels_per_m;
  if (options_.detector == DetectorKind::kLearned) {
    if (std::abs(pixels_per_m - kLearnedPixelsPerM) > 0.01 * kLearnedPixelsPerM) {
      char got[64];
      std::snprintf(got, sizeof got, "%g px for %g m",
                    static_cast<double>(options_.top_view.size_px), options_.top_view.extent_m);
      throw std::invalid_argument(
          std::string("perception: top_view: the learned detector needs 60 px a metre "
                      "(size_px 600, extent_m 10), got ") +
          got + "; the classical detector (--detector classical) takes any scale");
    }
    if (options_.learned_slots.model_path.empty()) {
      options_.learned_slots.model_path = DefaultModelDir() + "/marking_points.onnx";
    }
    if (options_.learned_ids.model_path.empty()) {
      options_.learned_ids.model_path = DefaultModelDir() + "/slot_ids.onnx";
    }
    learned_detector_ = std::make_unique<LearnedSlotDetector>(options_.learned_slots);
    if (options_.read_ids) {
      learned_reader_ = std::make_unique<LearnedSlotIdReader>(options_.learned_ids);
      if (options_.learned_ids_with_classical) {
        id_reader_ = std::make_unique<SlotIdReader>(options_.ids);
      }
    }
  } else {
    slot_detector_ = std::make_unique<SlotDetector>(options_.slots);
    if (options_.read_ids) id_reader_ = std::make_unique<SlotIdReader>(options_.ids);
  }
  tag_detector_ = std::make_unique<TagDetector>(options_.tags);
}

void PerceptionFrontEnd::MakeMasks() {
  // The car's own footprint carries no ground: the detector ignores it.
  const camera::TopViewOptions& tv = options_.top_view;
  footprint_mask_ = cv::Mat(tv.size_px, tv.size_px, CV_8UC1, cv::Scalar(255));
  if (tv.mask_footprint) {
    const double rear = -tv.footprint_rear_overhang_m;
    const double front = tv.footprint_length_m - tv.footprint_rear_overhang_m;
    const double half_w = tv.footprint_width_m / 2;
    const Eigen::Vector2d a = fusion_->VehicleToPixel({front, half_w});
    const Eigen::Vector2d b = fusion_->VehicleToPixel({rear, -half_w});
    const cv::Point tl(static_cast<int>(std::floor(std::min(a.x(), b.x()))),
                       static_cast<int>(std::floor(std::min(a.y(), b.y()))));
    const cv::Point br(static_cast<int>(std::ceil(std::max(a.x(), b.x()))) + 1,
                       static_cast<int>(std::ceil(std::max(a.y(), b.y()))) + 1);
    footprint_mask_(cv::Rect(tl, br) & cv::Rect(0, 0, tv.size_px, tv.size_px)).setTo(0);
  }
  // Each fisheye's part of the top view (with its blends and a margin of
  // kExcludedMarginPx), masked when that camera is left out.
  constexpr int kExcludedMarginPx = 5;
  for (std::size_t c = 0; c < options_.fisheye_cameras.size(); ++c) {
    cv::Mat region(tv.size_px, tv.size_px, CV_8UC1, cv::Scalar(0));
    for (int v = 0; v < tv.size_px; ++v) {
      for (int u = 0; u < tv.size_px; ++u) {
        const int k = static_cast<int>(c);
        if (fusion_->PrimaryCamera(u, v) == k || fusion_->SecondaryCamera(u, v) == k) {
          region.at<std::uint8_t>(v, u) = 255;
        }
      }
    }
    cv::dilate(region, region, cv::Mat(), cv::Point(-1, -1), kExcludedMarginPx);
    camera_regions_.push_back(region);
  }
}

PerceptionFrontEnd::~PerceptionFrontEnd() = default;

namespace {

bool IsExcluded(const std::vector<std::string>& excluded, const std::string& name) {
  return std::find(excluded.begin(), excluded.end(), name) != excluded.end();
}

// The frame's image of a camera; null when it has none.
const ImagePlane* ImageOf(const CameraFrame& frame, const std::string& name) {
  for (size_t k = 0; k < frame.cameras.size() && k < frame.images.size(); ++k) {
    if (frame.cameras[k] == name && frame.images[k].pixels != nullptr) return &frame.images[k];
  }
  return nullptr;
}

// A tag's observation in the vehicle frame from its pose in the camera
// (paper III-B): the ground-plane position x = sin(alpha) d to the right,
// y = cos(alpha) d ahead of the camera, the outward normal's yaw, and the
// covariance of range and bearing noise.
TagObservation TagObservationOf(const DetectedTag& t, const camera::CameraConfig& camera,
                                const PerceptionOptions& options) {
  const Eigen::Matrix3d R_vehicle_camera = camera.T_vehicle_camera.rotation();
  const Eigen::Vector3d camera_vehicle = camera.T_vehicle_camera.translation();
  // The camera's optical axis and right-hand direction on the ground.
  const Eigen::Vector3d z_axis = R_vehicle_camera.col(2), x_axis = R_vehicle_camera.col(0);
  const Eigen::Vector2d forward = Eigen::Vector2d(z_axis.x(), z_axis.y()).normalized();
  const Eigen::Vector2d right = Eigen::Vector2d(x_axis.x(), x_axis.y()).normalized();
  TagObservation obs;
  obs.tag_id = t.tag_id;
  const Eigen::Vector2d offset = t.position_m.x() * right + t.position_m.y() * forward;
  obs.p_vehicle = Eigen::Vector2d(camera_vehicle.x(), camera_vehicle.y()) + offset;
  obs.range_m = offset.norm();
  obs.bearing_rad = std::atan2(Cross2(forward, offset), forward.dot(offset));
  // Outward normal: the tag's z axis, signed to face the camera.
  Eigen::Vector3d n_camera = t.T_camera_tag.rotation().col(2);
  if (n_camera.dot(-t.T_camera_tag.translation()) < 0.0) n_camera = -n_camera;
  const Eigen::Vector3d n_vehicle = R_vehicle_camera * n_camera;
  obs.yaw_vehicle_rad = std::atan2(n_vehicle.y(), n_vehicle.x());
  obs.yaw_sigma_rad = options.tag_yaw_sigma_rad + options.tag_yaw_sigma_per_m * obs.range_m;
  const double range_sigma =
      options.tag_range_sigma_m + options.tag_range_sigma_per_m * obs.range_m;
  const double bearing_sigma = options.tag_bearing_sigma_rad;
  // J diag(sr^2, sb^2) J^T, J = d(point)/d(range, bearing), in the
  // vehicle frame along (forward, left) of the camera.
  const Eigen::Vector2d u = offset / std::max(obs.range_m, 1e-6);
  const Eigen::Vector2d v(-u.y(), u.x());
  obs.covariance_vehicle = range_sigma * range_sigma * u * u.transpose() +
                           std::pow(obs.range_m * bearing_sigma, 2) * v * v.transpose();
  return obs;
}

}  // namespace

PerceptionOutput PerceptionFrontEnd::Process(const CameraFrame& frame,
                                             const std::vector<std::string>& excluded) const {
  PerceptionOutput out;
  out.slots.t_ns = frame.t_ns;
  out.tags.t_ns = frame.t_ns;
  PerceiveSlots(frame, excluded, &out);
  PerceiveTags(frame, excluded, &out);
  return out;
}

void PerceptionFrontEnd::PerceiveSlots(const CameraFrame& frame,
                                       const std::vector<std::string>& excluded,
                                       PerceptionOutput* out) const {
  cv::Mat mask = footprint_mask_;
  if (const ImagePlane* given = ImageOf(frame, kTopViewCamera)) {
    // Fused elsewhere, in this front end's geometry.
    if (given->width != footprint_mask_.cols || given->height != footprint_mask_.rows) {
      throw std::invalid_argument(
          std::string("front end: the frame's ") + kTopViewCamera + " is " +
          std::to_string(given->width) + " x " + std::to_string(given->height) +
          " px, and the top view here is " + std::to_string(footprint_mask_.cols) + " x " +
          std::to_string(footprint_mask_.rows) + " (front_end.top_view.size_px)");
    }
    if (IsExcluded(excluded, kTopViewCamera)) return;
    out->top_view = camera::AsMat(*given).clone();
    DetectAndRead(mask, out);
    return;
  }
  // A left-out fisheye is fused as black (what no camera sees) and its part
  // of the top view masked.
  std::vector<cv::Mat> fisheyes;
  std::size_t left_out = 0;
  for (std::size_t c = 0; c < options_.fisheye_cameras.size(); ++c) {
    const std::string& name = options_.fisheye_cameras[c];
    const ImagePlane* plane = ImageOf(frame, name);
    if (plane == nullptr) break;
    if (!IsExcluded(excluded, name)) {
      fisheyes.push_back(camera::AsMat(*plane));
      continue;
    }
    fisheyes.push_back(cv::Mat::zeros(plane->height, plane->width, CV_8UC1));
    if (left_out++ == 0) mask = footprint_mask_.clone();
    mask.setTo(0, camera_regions_[c]);
  }
  if (fisheyes.size() != options_.fisheye_cameras.size() || left_out >= fisheyes.size()) return;
  const Clock::time_point start = Clock::now();
  out->top_view = fusion_->Fuse(fisheyes);
  out->timing.fusion_ms = MsSince(start);
  DetectAndRead(mask, out);
}

void PerceptionFrontEnd::DetectAndRead(const cv::Mat& mask, PerceptionOutput* out) const {
  Clock::time_point start = Clock::now();
  out->detection = learned_detector_ != nullptr ? learned_detector_->Detect(out->top_view, mask)
                                                : slot_detector_->Detect(out->top_view, mask);
  out->timing.slots_ms = MsSince(start);
  start = Clock::now();
  out->ids.resize(out->detection.slots.size());
  for (size_t k = 0; k < out->detection.slots.size(); ++k) {
    const DetectedSlot& slot = out->detection.slots[k];
    const EntranceInImage entrance{slot.corners_px[0], slot.corners_px[1], slot.depth_dir_px};
    if (id_reader_ != nullptr) out->ids[k] = id_reader_->Read(out->top_view, entrance);
    if (learned_reader_ == nullptr) continue;
    // Both readers: the classical one's reading stands where it reads
    // every digit surely; the network reads the others.
    const SlotIdReading& classical = out->ids[k];
    if (id_reader_ != nullptr && !classical.empty() && !classical.partial() &&
        classical.confidence() >= options_.classical_id_min_confidence) {
      continue;
    }
    out->ids[k] = learned_reader_->Read(out->top_view, entrance);
  }
  out->timing.ids_ms = MsSince(start);
  const Eigen::Vector2d view_centre_vehicle(options_.top_view.center_x_m, 0.0);
  for (size_t k = 0; k < out->detection.slots.size(); ++k) {
    const DetectedSlot& slot = out->detection.slots[k];
    SlotObservation obs;
    double far_m = 0.0;
    for (int c = 0; c < kSlotCorners; ++c) {
      obs.corners_vehicle[static_cast<size_t>(c)] =
          fusion_->PixelToVehicle(slot.corners_px[static_cast<size_t>(c)]);
      obs.corner_observed[static_cast<size_t>(c)] = slot.corner_observed[static_cast<size_t>(c)];
      if (c < 2) {
        far_m = std::max(
            far_m, (obs.corners_vehicle[static_cast<size_t>(c)] - view_centre_vehicle).norm());
      }
    }
    obs.corner_sigma_m = options_.corner_sigma_m + options_.corner_sigma_per_m * far_m;
    obs.detection_confidence = slot.confidence;
    obs.id = out->ids[k];
    out->slots.slots.push_back(obs);
  }
}

void PerceptionFrontEnd::PerceiveTags(const CameraFrame& frame,
                                      const std::vector<std::string>& excluded,
                                      PerceptionOutput* out,
                                      const std::vector<TagWindow>* windows) const {
  if (IsExcluded(excluded, options_.tag_camera)) return;
  const ImagePlane* plane = ImageOf(frame, options_.tag_camera);
  if (plane == nullptr) return;
  const Clock::time_point start = Clock::now();
  const cv::Mat image = camera::AsMat(*plane);
  if (image.cols != tag_camera_.intrinsics.width || image.rows != tag_camera_.intrinsics.height) {
    throw std::invalid_argument("perception: the " + options_.tag_camera + " image is " +
                                std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                                ", the camera " + std::to_string(tag_camera_.intrinsics.width) +
                                "x" + std::to_string(tag_camera_.intrinsics.height));
  }
  std::vector<DetectedTag> tags;
  if (windows == nullptr) {
    tags = tag_detector_->Detect(image.rowRange(tag_first_row_, tag_first_row_ + tag_rows_),
                                 &tag_band_intrinsics_);
  } else {
    const cv::Rect whole(0, 0, image.cols, image.rows);
    std::vector<bool> from_own_window;
    for (const TagWindow& window : *windows) {
      const cv::Rect w = window.rect & whole;
      if (w.empty()) continue;
      // The window as a camera of its own: the principal point moves.
      camera::CameraIntrinsics k = tag_camera_.intrinsics;
      k.width = w.width;
      k.height = w.height;
      k.cx -= w.x;
      k.cy -= w.y;
      for (DetectedTag& t :
           tag_detector_->Detect(image(w), &k, static_cast<float>(window.decimate))) {
        const Eigen::Vector2d offset(w.x, w.y);
        for (Eigen::Vector2d& c : t.corners_px) c += offset;
        t.center_px += offset;
        // A tag found twice is kept once, from the window made for it.
        const bool own = t.tag_id == window.tag_id;
        const auto seen = std::find_if(tags.begin(), tags.end(),
                                       [&](const DetectedTag& d) { return d.tag_id == t.tag_id; });
        if (seen == tags.end()) {
          tags.push_back(t);
          from_own_window.push_back(own);
        } else if (own && !from_own_window[static_cast<size_t>(seen - tags.begin())]) {
          *seen = t;
          from_own_window[static_cast<size_t>(seen - tags.begin())] = true;
        }
      }
    }
  }
  out->timing.tags_ms = MsSince(start);
  for (const DetectedTag& t : tags) {
    if (t.has_pose) out->tags.tags.push_back(TagObservationOf(t, tag_camera_, options_));
  }
}

std::optional<std::vector<TagWindow>> PerceptionFrontEnd::TagWindows(
    const std::vector<MapTag>& tags, const SE2& T_map_vehicle,
    const Eigen::Matrix3d& covariance) const {
  const TagWindowOptions& o = options_.tag_windows;
  if (!o.enabled) return std::nullopt;
  // The poses the windows must hold: the estimate and its sigma points,
  // x +- sigmas L e_i with P = L L^T (x, y, yaw).
  if (!covariance.allFinite()) return std::nullopt;
  const Eigen::LLT<Eigen::Matrix3d> llt(covariance);
  if (llt.info() != Eigen::Success) return std::nullopt;
  const Eigen::Matrix3d L = llt.matrixL();
  std::vector<SE2> poses{T_map_vehicle};
  for (int i = 0; i < 3; ++i) {
    for (const double sign : {-1.0, 1.0}) {
      const Eigen::Vector3d d = sign * o.sigmas * L.col(i);
      poses.emplace_back(T_map_vehicle.x() + d.x(), T_map_vehicle.y() + d.y(),
                         T_map_vehicle.yaw() + d.z());
    }
  }
  const camera::CameraIntrinsics& k = tag_camera_.intrinsics;
  const Eigen::Isometry3d T_camera_vehicle = tag_camera_.T_vehicle_camera.inverse();
  const Eigen::Vector2d camera_vehicle = tag_camera_.T_vehicle_camera.translation().head<2>();
  const double mid_height_m = 0.5 * (options_.tag_min_height_m + options_.tag_max_height_m);
  const int fine = std::max(1, static_cast<int>(std::lround(options_.tags.quad_decimate)));
  const cv::Rect band(0, tag_first_row_, k.width, tag_rows_);
  const auto cost = [](const TagWindow& w) {
    return static_cast<double>(w.rect.area()) / (w.decimate * w.decimate);
  };
  std::vector<TagWindow> windows;
  for (const MapTag& tag : tags) {
    // In view at the estimate: in range, facing the camera.
    const Eigen::Vector2d camera_map = T_map_vehicle * camera_vehicle;
    const Eigen::Vector2d to_camera = camera_map - tag.p_map;
    const Eigen::Vector2d normal(std::cos(tag.yaw_map_rad), std::sin(tag.yaw_map_rad));
    if (to_camera.norm() >= options_.tags.max_range_m || normal.dot(to_camera) <= 0.0) continue;
    // The tag's two vertical edges, at the heights a tag can have, from
    // every pose; and its height in pixels from the farthest.
    const Eigen::Vector2d along(-normal.y(), normal.x());
    double u_min = std::numeric_limits<double>::infinity(), u_max = -u_min;
    double v_min = u_min, v_max = -u_min;
    double farthest_m = 0.0;
    int ahead = 0;
    for (const SE2& T : poses) {
      const SE2 T_vehicle_map = T.inverse();
      const Eigen::Vector2d centre = T_vehicle_map * tag.p_map;
      farthest_m =
          std::max(farthest_m,
                   (T_camera_vehicle * Eigen::Vector3d(centre.x(), centre.y(), mid_height_m)).z());
      for (const double side : {-0.5, 0.5}) {
        const Eigen::Vector2d p = T_vehicle_map * (tag.p_map + side * tag.size_m * along);
        for (const double z : {options_.tag_min_height_m, options_.tag_max_height_m}) {
          const Eigen::Vector3d c = T_camera_vehicle * Eigen::Vector3d(p.x(), p.y(), z);
          if (c.z() < 0.2) continue;
          ++ahead;
          const double u = k.cx + k.fx * c.x() / c.z(), v = k.cy + k.fy * c.y() / c.z();
          u_min = std::min(u_min, u);
          u_max = std::max(u_max, u);
          v_min = std::min(v_min, v);
          v_max = std::max(v_max, v);
        }
      }
    }
    if (ahead == 0) continue;
    // Grown by the margin, aligned to 8 pixels (the coarsest decimation),
    // inside the band.
    const double big = 1e6;
    const auto down = [&](double x) {
      return static_cast<int>(std::floor(std::clamp(x, -big, big) / 8.0)) * 8;
    };
    const auto up = [&](double x) {
      return static_cast<int>(std::ceil(std::clamp(x, -big, big) / 8.0)) * 8;
    };
    const double m = o.margin_px;
    const int x0 = down(u_min - m), x1 = up(u_max + m), y0 = down(v_min - m), y1 = up(v_max + m);
    TagWindow window;
    window.rect = cv::Rect(x0, y0, x1 - x0, y1 - y0) & band;
    window.tag_id = tag.tag_id;
    if (window.rect.empty()) continue;
    // The coarsest decimation that keeps the tag min_decimated_px high.
    const double tag_px = farthest_m > 0.2 ? k.fy * tag.size_m / farthest_m : 0.0;
    window.decimate = fine;
    while (window.decimate * 2 <= 8 && tag_px / (window.decimate * 2) >= o.min_decimated_px) {
      window.decimate *= 2;
    }
    windows.push_back(window);
  }
  // Overlapping windows become their bounding box where that costs no
  // more than searching both, until none can.
  for (bool merged = true; merged;) {
    merged = false;
    for (size_t i = 0; i < windows.size() && !merged; ++i) {
      for (size_t j = i + 1; j < windows.size(); ++j) {
        if ((windows[i].rect & windows[j].rect).empty()) continue;
        TagWindow both;
        both.rect = windows[i].rect | windows[j].rect;
        both.decimate = std::min(windows[i].decimate, windows[j].decimate);
        if (cost(both) > cost(windows[i]) + cost(windows[j])) continue;
        windows[i] = both;
        windows.erase(windows.begin() + static_cast<std::ptrdiff_t>(j));
        merged = true;
        break;
      }
    }
  }
  double total = 0.0;
  for (const TagWindow& w : windows) total += cost(w);
  if (total > o.max_band_share * band.area() / (fine * fine)) return std::nullopt;
  return windows;
}

PerceptionSource::PerceptionSource(SensorSource& inner, const PerceptionFrontEnd& front_end)
    : inner_(inner), front_end_(front_end) {}

void PerceptionSource::Count(const PerceptionTiming& timing) {
  total_timing_.fusion_ms += timing.fusion_ms;
  total_timing_.slots_ms += timing.slots_ms;
  total_timing_.ids_ms += timing.ids_ms;
  total_timing_.tags_ms += timing.tags_ms;
  max_frame_ms_ = std::max(max_frame_ms_, timing.total_ms());
}

std::optional<SensorEvent> PerceptionSource::Next() {
  if (pending_tags_) {
    std::optional<SensorEvent> event = std::move(pending_tags_);
    pending_tags_.reset();
    return event;
  }
  if (pending_frame_) {
    // The slots have been taken: the tags, where the consumer expects them.
    PendingFrame p = std::move(*pending_frame_);
    pending_frame_.reset();
    const std::optional<std::vector<TagWindow>> windows = tag_windows_(p.frame.t_ns);
    front_end_.PerceiveTags(p.frame, p.excluded, &p.out, windows ? &*windows : nullptr);
    Count(p.out.timing);
    return SensorEvent(std::move(p.out.tags));
  }
  while (std::optional<SensorEvent> event = inner_.Next()) {
    if (std::holds_alternative<SlotObservationFrame>(*event) ||
        std::holds_alternative<TagObservationFrame>(*event)) {
      continue;  // only what the cameras see
    }
    if (auto* frame = std::get_if<CameraFrame>(&*event)) {
      // Black or frozen cameras are left out while they are so.
      const std::vector<CameraHealth> health = health_.Check(*frame);
      std::vector<std::string> excluded;
      for (std::size_t k = 0; k < health.size(); ++k) {
        if (health[k] != CameraHealth::kOk) excluded.push_back(frame->cameras[k]);
      }
      ++frames_processed_;
      if (tag_windows_) {
        PendingFrame p;
        p.out.slots.t_ns = p.out.tags.t_ns = frame->t_ns;
        front_end_.PerceiveSlots(*frame, excluded, &p.out);
        SensorEvent slots(std::move(p.out.slots));
        p.frame = std::move(*frame);
        p.excluded = std::move(excluded);
        pending_frame_ = std::move(p);
        return slots;
      }
      PerceptionOutput out = front_end_.Process(*frame, excluded);
      Count(out.timing);
      pending_tags_ = std::move(out.tags);
      return SensorEvent(std::move(out.slots));
    }
    return event;
  }
  return std::nullopt;
}

}  // namespace parkslam::perception
