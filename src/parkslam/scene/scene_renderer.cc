#include "parkslam/scene/scene_renderer.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <future>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <thread>

#include "parkslam/common/angles.h"
#include "parkslam/common/random.h"
#include "parkslam/common/seed_mix.h"
#include "parkslam/scene/floor_painter.h"
#include "parkslam/scene/tag_texture.h"

namespace parkslam::scene {
namespace {

constexpr int kAtlasGap = 4;
constexpr int kNoiseBankSize = 509;  // prime: offsets never line up with image rows
constexpr float kInf = std::numeric_limits<float>::infinity();
// Footprints finer than this sample the 2 cm floor, coarser ones the 4 cm
// level; beyond the top view's square, the 10 cm floor.
constexpr double kMaxFootprintNearM = 0.035;
constexpr double kSpecularCellM = 0.1;
constexpr double kMaxOffAxisRad = 1.66;        // 95 degrees: a 190-degree lens
constexpr float kAutoExposureTarget = 115.0f;  // mean grey level the cameras meter for
constexpr float kHighlightLevel = 235.0f;      // where a lot's cameras keep their highlights
constexpr double kSpecularHalfExtentM = 10.0;

// kFarGround: the floor beyond the scene's atlas (a lot's floor reaches
// there; a scene's does not: its dark below the horizon).
enum PixelKind : std::uint8_t { kNone, kGround, kUp, kEgo, kFarGround };

// The floor at three resolutions side by side, so that one remap per camera
// samples each pixel's footprint.
struct AtlasLayout {
  cv::Rect near, mid, far;
  cv::Size size;
};

// Pixels sorted by the azimuth of their ray, with what the solids' scan
// reads first, contiguous in that order.
struct AzimuthIndex {
  std::vector<float> azimuth;  // radians in (-pi, pi]
  std::vector<int> pixel;
  std::vector<float> reach;  // horizontal reach before the floor (-1: the car's body)
  // The same on a lot's floor, which reaches everywhere (floor_reach), and
  // indoors under its ceiling too (roofed_reach).
  std::vector<float> floor_reach, roofed_reach;
  void Add(float a, int i, float r, float floor_r, float roofed_r) {
    azimuth.push_back(a);
    pixel.push_back(i);
    reach.push_back(r);
    floor_reach.push_back(floor_r);
    roofed_reach.push_back(roofed_r);
  }
};

struct CameraTable {
  std::string name;
  camera::CameraConfig config;
  int width = 0, height = 0;
  double pixel_angle_rad = 0.0;  // of one pixel near the axis
  Eigen::Vector3d c_vehicle = Eigen::Vector3d::Zero();
  cv::Mat map_xy, map_frac;  // fixed-point maps into the atlas
  cv::Mat kind;              // CV_8U PixelKind
  cv::Mat vignette;          // CV_32F, squared off-axis angle over its maximum
  cv::Mat ego_shade;         // CV_32F, where kind is kEgo
  cv::Mat ego;               // CV_8U, 255 where kind is kEgo: the floor the car's body hides
  cv::Mat needed;            // CV_8U, 255 where the top view samples (with a margin for blur)
  cv::Mat metered;           // CV_8U, 255 where the top view samples: what auto exposure meters
  cv::Range needed_rows = cv::Range::all();  // the rows that hold any of them
  std::vector<Eigen::Vector3f> rays;         // unit, vehicle frame
  std::vector<float> ground_t;               // along the ray to the floor; inf where none
  std::vector<float> horizontal;             // horizontal length of the unit ray
  std::vector<Eigen::Vector2f> ground_xy;
  std::vector<float> footprint;  // the pixel's footprint on the floor, metres
  std::vector<float> floor_t;    // along the ray to the floor wherever it meets it; inf up
  std::vector<float> roofed_t;   // the same under the ceiling (indoors: every rising ray ends)
  AzimuthIndex all_pixels;       // every valid pixel
  AzimuthIndex needed_pixels;    // those the top view needs
};

struct SolidHit {
  float t = kInf;
  Eigen::Vector3f normal = Eigen::Vector3f::UnitZ();
  bool top = false;
};

// A ray (origin o, unit direction d) against a box solid whose yaw has
// cosine cy and sine sy: slabs in the box's frame.
bool IntersectBox(const Solid& s, double cy, double sy, const Eigen::Vector3d& o,
                  const Eigen::Vector3f& d, SolidHit* hit) {
  const double ox = o.x() - s.center.x(), oy = o.y() - s.center.y();
  const double lo[3] = {-s.half_x, -s.half_y, s.z0}, hi[3] = {s.half_x, s.half_y, s.z1};
  const double lo_o[3] = {cy * ox + sy * oy, -sy * ox + cy * oy, o.z()};
  const double ld[3] = {cy * d.x() + sy * d.y(), -sy * d.x() + cy * d.y(), d.z()};
  double enter = -1e30, leave = 1e30;
  int axis = -1;
  double sign = 1;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(ld[k]) < 1e-12) {
      if (lo_o[k] < lo[k] || lo_o[k] > hi[k]) return false;
      continue;
    }
    double t0 = (lo[k] - lo_o[k]) / ld[k], t1 = (hi[k] - lo_o[k]) / ld[k];
    double face_sign = -1;
    if (t0 > t1) {
      std::swap(t0, t1);
      face_sign = 1;
    }
    if (t0 > enter) {
      enter = t0;
      axis = k;
      sign = face_sign;
    }
    leave = std::min(leave, t1);
  }
  if (axis < 0 || enter > leave || enter < 1e-3 || enter >= hit->t) return false;
  hit->t = static_cast<float>(enter);
  Eigen::Vector3f n = Eigen::Vector3f::Zero();
  if (axis == 0)
    n = Eigen::Vector3f(static_cast<float>(sign * cy), static_cast<float>(sign * sy), 0);
  if (axis == 1)
    n = Eigen::Vector3f(static_cast<float>(-sign * sy), static_cast<float>(sign * cy), 0);
  if (axis == 2) n = Eigen::Vector3f(0, 0, static_cast<float>(sign));
  hit->normal = n;
  hit->top = axis == 2 && sign > 0;
  return true;
}

// A ray against a vertical cylinder or cone.
bool IntersectRound(const Solid& s, const Eigen::Vector3d& o, const Eigen::Vector3f& d,
                    SolidHit* hit) {
  const double ox = o.x() - s.center.x(), oy = o.y() - s.center.y();
  // Vertical cylinder or cone: radius(z) = r0 - k (z - z0).
  const double r0 = s.half_x;
  const double k = s.shape == SolidShape::kCone ? r0 / std::max(1e-6, s.z1 - s.z0) : 0.0;
  const double e = r0 - k * (o.z() - s.z0), g = -k * d.z();
  const double a = d.x() * d.x() + d.y() * d.y() - g * g;
  const double b = 2 * (ox * d.x() + oy * d.y() - e * g);
  const double c = ox * ox + oy * oy - e * e;
  double best = hit->t;
  bool found = false;
  Eigen::Vector3f normal;
  bool top = false;
  if (std::abs(a) > 1e-12) {
    const double disc = b * b - 4 * a * c;
    if (disc >= 0) {
      const double sq = std::sqrt(disc);
      for (const double t : {(-b - sq) / (2 * a), (-b + sq) / (2 * a)}) {
        const double z = o.z() + t * d.z();
        if (t > 1e-3 && t < best && z >= s.z0 && z <= s.z1 && e + g * t >= 0) {
          best = t;
          found = true;
          const double px = ox + t * d.x(), py = oy + t * d.y();
          const double r = std::max(1e-6, std::hypot(px, py));
          normal = Eigen::Vector3f(static_cast<float>(px / r), static_cast<float>(py / r),
                                   static_cast<float>(k))
                       .normalized();
          top = false;
          break;
        }
      }
    }
  }
  if (s.shape == SolidShape::kCylinder && d.z() < 0) {
    const double t = (s.z1 - o.z()) / d.z();
    const double px = ox + t * d.x(), py = oy + t * d.y();
    if (t > 1e-3 && t < best && px * px + py * py <= r0 * r0) {
      best = t;
      found = true;
      normal = Eigen::Vector3f::UnitZ();
      top = true;
    }
  }
  if (!found) return false;
  hit->t = static_cast<float>(best);
  hit->normal = normal;
  hit->top = top;
  return true;
}

// A ray against a box whose vertical edges are rounded with radius r: the
// union of two boxes, one r shorter and one r narrower, and four vertical
// cylinders of radius r at the inner corners. Each piece keeps a hit only
// when it is nearer, so the union's nearest hit comes out of trying all.
bool IntersectRoundedBox(const Solid& s, double cy, double sy, const Eigen::Vector3d& o,
                         const Eigen::Vector3f& d, SolidHit* hit) {
  // The whole box bounds the rounded one: most rays miss both.
  SolidHit bound = *hit;
  if (!IntersectBox(s, cy, sy, o, d, &bound)) return false;
  const double r = std::min({s.corner_radius_m, s.half_x, s.half_y});
  bool found = false;
  Solid piece = s;
  piece.corner_radius_m = 0.0;
  piece.half_y = s.half_y - r;
  found |= IntersectBox(piece, cy, sy, o, d, hit);
  piece.half_x = s.half_x - r;
  piece.half_y = s.half_y;
  found |= IntersectBox(piece, cy, sy, o, d, hit);
  piece.shape = SolidShape::kCylinder;
  piece.half_x = r;
  const Eigen::Vector2d ax(cy, sy), ay(-sy, cy);
  for (int kx = -1; kx <= 1; kx += 2) {
    for (int ky = -1; ky <= 1; ky += 2) {
      piece.center = s.center + ax * (kx * (s.half_x - r)) + ay * (ky * (s.half_y - r));
      found |= IntersectRound(piece, o, d, hit);
    }
  }
  return found;
}

// Ray (origin o, unit direction d) against a solid; the nearest hit beyond
// a millimetre, if any.
bool Intersect(const Solid& s, double cy, double sy, const Eigen::Vector3d& o,
               const Eigen::Vector3f& d, SolidHit* hit) {
  if (s.shape == SolidShape::kBox) {
    return s.corner_radius_m > 0 ? IntersectRoundedBox(s, cy, sy, o, d, hit)
                                 : IntersectBox(s, cy, sy, o, d, hit);
  }
  return IntersectRound(s, o, d, hit);
}

// A solid's own horizontal frame: x along its yaw.
struct SolidFrame {
  double cos_yaw = 1.0, sin_yaw = 0.0;
  explicit SolidFrame(const Solid& s)
      : cos_yaw(std::cos(s.yaw_rad)), sin_yaw(std::sin(s.yaw_rad)) {}
  // Coordinates of the map point p relative to the solid's centre, in its frame.
  Eigen::Vector2d Local(const Solid& s, const Eigen::Vector2d& p) const {
    const Eigen::Vector2d d = p - s.center;
    return {cos_yaw * d.x() + sin_yaw * d.y(), -sin_yaw * d.x() + cos_yaw * d.y()};
  }
};

float Luma(const cv::Vec3f& p) { return 0.114f * p[0] + 0.587f * p[1] + 0.299f * p[2]; }

// What stands against the sky outdoors, by azimuth: a wavy tree line
// (positive elevation, radians) or, in some directions, a building's flat
// roof line (negative: a building). Only whole fisheye images show it.
float SkylineElevation(std::uint64_t seed, float azimuth) {
  const float a = static_cast<float>(MixSeed(seed, 1) % 628) / 100.0f;
  const float b = static_cast<float>(MixSeed(seed, 2) % 628) / 100.0f;
  const int sector = static_cast<int>(
      std::floor((azimuth + static_cast<float>(kPi)) / (2 * static_cast<float>(kPi)) * 12.0f));
  const std::uint64_t h = MixSeed(seed, 100 + static_cast<std::uint64_t>(sector));
  if (h % 4 == 0) return -(0.2f + static_cast<float>(h % 1000) / 4000.0f);
  return 0.1f + 0.05f * std::sin(3.0f * azimuth + a) + 0.03f * std::sin(11.0f * azimuth + b) +
         0.015f * std::sin(29.0f * azimuth);
}

}  // namespace

bool SceneRendererOptions::IsValid(std::string* error) const {
  const auto fail = [error](const char* what) {
    if (error != nullptr) *error = what;
    return false;
  };
  if (fisheye_names.empty()) return fail("fisheye_names is empty");
  if (!(near_resolution_m > 0.002 && near_resolution_m < 0.2))
    return fail("near_resolution_m must be in (0.002, 0.2)");
  if (!(near_max_x_m > near_min_x_m && near_half_width_m > 0))
    return fail("the near floor must have an area");
  if (!(far_resolution_m >= near_resolution_m && far_half_extent_m > 1.0)) {
    return fail(
        "far_resolution_m must be at least near_resolution_m and far_half_extent_m above 1");
  }
  if (perturbed_calibrations < 0 || perturbed_calibrations > 64)
    return fail("perturbed_calibrations must be in [0, 64]");
  if (!(calibration_rotation_sigma_rad >= 0 && calibration_translation_sigma_m >= 0)) {
    return fail("calibration sigmas must be non-negative");
  }
  if (!(ceiling_height_m > 1.5)) return fail("ceiling_height_m must exceed 1.5");
  std::string top_error;
  if (!top_view.IsValid(&top_error)) return fail("top_view is invalid");
  if (seam_layouts.empty()) return fail("seam_layouts is empty");
  for (const std::vector<double>& layout : seam_layouts) {
    if (layout.size() != fisheye_names.size())
      return fail("every seam layout needs one priority per fisheye");
  }
  for (const double angle : ray_seam_angles_rad) {
    if (!(angle > 0 && angle < M_PI / 2)) return fail("ray_seam_angles_rad must be in (0, pi/2)");
  }
  return true;
}

struct SceneRenderer::Impl {
  SceneRendererOptions options;
  camera::CameraRig rig;
  std::vector<camera::CameraConfig> fisheye_configs;
  std::vector<camera::CameraModel> fisheye_models;
  // Calibration k, seam layout l: fusions[k * layouts + l]; k = 0 exact.
  // Each is built when a scene first asks for it (Fusion()), from any
  // thread: most runs use a few of them.
  struct LazyFusion {
    std::once_flag built;
    std::unique_ptr<camera::TopViewFusion> fusion;
  };
  std::vector<std::unique_ptr<LazyFusion>> fusions;
  std::vector<camera::CameraRig> fusion_rigs;
  std::vector<CameraTable> fisheyes;
  std::optional<CameraTable> front;
  AtlasLayout atlas;
  cv::Mat noise_bank;  // CV_32F standard normal
  // Tag textures by ID (16, 8, 4, 2, 1 pixels a cell), made when first
  // seen.
  mutable std::mutex tag_mutex;
  mutable std::map<int, std::array<cv::Mat, 5>> tag_textures;
  const std::array<cv::Mat, 5>& TagTexture(int tag_id) const;
  // Every pixel's place in a painted floor for the car at (yaw, t): full,
  // or the pixels the top view needs.
  cv::Mat FloorMap(const CameraTable& t, const FloorAtlas& floor, double yaw_rad,
                   const Eigen::Vector2d& tr, bool full) const;
  // The tags the camera sees, over the background; their depth into depth.
  void ShadeTags(const CameraTable& t, const Scene& scene, const LightMap& light, cv::Mat* radiance,
                 std::vector<float>* depth) const;

  Impl(const camera::CameraRig& r, const SceneRendererOptions& o);
  int Layouts() const {
    return static_cast<int>(options.seam_layouts.size() + options.ray_seam_angles_rad.size());
  }
  // Calibration k (0: exact), seam layout l (the optical-axis layouts, then
  // the straight ones).
  const camera::TopViewFusion& Fusion(int k, int l) const;
  CameraTable BuildTable(const camera::CameraConfig& config) const;
  cv::Point2f AtlasPixel(const Eigen::Vector2d& g, double footprint) const;
  // full: every pixel; otherwise only those the top view needs (the rest black).
  // floor_map: where each pixel samples atlas_bgr (FloorMap); null: the
  // table's own maps into the scene's atlas.
  cv::Mat RenderCamera(const CameraTable& table, const Scene& scene, const CameraLook& look,
                       const cv::Mat& atlas_bgr, const LightMap& light, const Colour& ego_colour,
                       bool full, cv::Mat* solid_mask, const cv::Mat* floor_map = nullptr) const;
  // far_floor: the floor beyond the scene's atlas is in `ground` too.
  void ShadeBackground(const CameraTable& t, const Scene& scene, const LightMap& light,
                       const Colour& ego_colour, const cv::Mat& ground, const cv::Mat& specular,
                       const std::uint8_t* need, const cv::Range& rows, bool far_floor,
                       cv::Mat* radiance) const;
  // depth: the nearest surface so far along each pixel (null: the floor).
  void ShadeSolids(const CameraTable& t, const Scene& scene, const LightMap& light,
                   const std::uint8_t* need, cv::Mat* radiance, cv::Mat* solid_mask,
                   const std::vector<float>* depth = nullptr) const;
  void ApplyLook(const CameraLook& look, const CameraTable& table, float gain, bool full,
                 cv::Mat* radiance, cv::Mat* out8) const;
  // What a pass from radiance to 8 bits applies: gains per channel,
  // vignetting, the noise bank's offsets and sigma; masked: only the pixels
  // the top view needs.
  struct DevelopParams {
    float gain[3] = {1.0f, 1.0f, 1.0f};
    float vignetting = 0.0f;
    int ox0 = 0, oy0 = 0, ox1 = 0, ox2 = 0;
    float sigma = 0.0f;
    bool masked = false;
  };
  void Develop(const cv::Mat& img, const CameraTable& table, const DevelopParams& params,
               bool light, bool noise, cv::Mat* out8) const;
  void MarkNeeded();
  // The fisheyes' ground pixels of an 8-bit atlas fused into a top view,
  // with `hide` (per camera, may be null) blacked out.
  cv::Mat FuseGrey(const camera::TopViewFusion& fusion, const cv::Mat& atlas8,
                   const std::vector<cv::Mat>* hide) const;
  // A 2 cm dot on every marking point, at every level of the floor, fused.
  cv::Mat MarkDots(const camera::TopViewFusion& fusion, const Scene& scene, const Canvas& near,
                   const Canvas& far) const;
  // The floor's three levels side by side: near, near halved, far.
  cv::Mat Stack(const cv::Mat& near, const cv::Mat& far) const {
    cv::Mat stacked(atlas.size, near.type(), cv::Scalar::all(0));
    near.copyTo(stacked(atlas.near));
    cv::Mat half;
    cv::pyrDown(near, half, atlas.mid.size());
    half.copyTo(stacked(atlas.mid));
    far.copyTo(stacked(atlas.far));
    return stacked;
  }
  // The near floor's place in the far one, when its edges fall on far
  // pixels' edges (the defaults do); empty otherwise.
  cv::Rect NearInFar() const {
    const double f = options.far_resolution_m;
    const double x0 = (options.near_min_x_m + options.far_half_extent_m) / f;
    const double y0 = (options.far_half_extent_m - options.near_half_width_m) / f;
    const double w = (options.near_max_x_m - options.near_min_x_m) / f,
                 h = 2 * options.near_half_width_m / f;
    const auto whole = [](double v) { return std::abs(v - std::round(v)) < 1e-6; };
    if (!whole(x0) || !whole(y0) || !whole(w) || !whole(h)) return {};
    const cv::Rect r(static_cast<int>(std::lround(x0)), static_cast<int>(std::lround(y0)),
                     static_cast<int>(std::lround(w)), static_cast<int>(std::lround(h)));
    return r == (r & cv::Rect(0, 0, atlas.far.width, atlas.far.height)) ? r : cv::Rect();
  }
};

SceneRenderer::Impl::Impl(const camera::CameraRig& r, const SceneRendererOptions& o)
    : options(o), rig(r) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument("scene renderer: " + error);
  const double near_w = options.near_max_x_m - options.near_min_x_m;
  const cv::Size near(
      static_cast<int>(std::lround(near_w / options.near_resolution_m)),
      static_cast<int>(std::lround(2 * options.near_half_width_m / options.near_resolution_m)));
  const cv::Size mid((near.width + 1) / 2, (near.height + 1) / 2);
  const int far_n =
      static_cast<int>(std::lround(2 * options.far_half_extent_m / options.far_resolution_m));
  atlas.near = cv::Rect(0, 0, near.width, near.height);
  atlas.mid = cv::Rect(near.width + kAtlasGap, 0, mid.width, mid.height);
  atlas.far = cv::Rect(atlas.mid.x + mid.width + kAtlasGap, 0, far_n, far_n);
  atlas.size = cv::Size(atlas.far.x + far_n, std::max(near.height, far_n));

  for (const std::string& name : options.fisheye_names) {
    const camera::CameraConfig* c = rig.Find(name);
    if (c == nullptr)
      throw std::invalid_argument("scene renderer: the rig has no camera '" + name + "'");
    fisheye_configs.push_back(*c);
    fisheye_models.emplace_back(c->intrinsics);
    fisheyes.push_back(BuildTable(*c));
  }
  if (!options.front_camera.empty()) {
    const camera::CameraConfig* c = rig.Find(options.front_camera);
    if (c == nullptr) {
      throw std::invalid_argument("scene renderer: the rig has no camera '" + options.front_camera +
                                  "'");
    }
    front = BuildTable(*c);
  }
  fusion_rigs.push_back(rig);
  for (int k = 1; k <= options.perturbed_calibrations; ++k) {
    fusion_rigs.push_back(camera::PerturbExtrinsics(
        rig, options.calibration_rotation_sigma_rad, options.calibration_translation_sigma_m,
        MixSeed(options.calibration_seed, static_cast<std::uint64_t>(k))));
  }
  for (size_t k = 0; k < fusion_rigs.size() * static_cast<size_t>(Layouts()); ++k) {
    fusions.push_back(std::make_unique<LazyFusion>());
  }
  MarkNeeded();
  noise_bank = cv::Mat(kNoiseBankSize, kNoiseBankSize, CV_32F);
  cv::RNG rng(0x5eed);
  rng.fill(noise_bank, cv::RNG::NORMAL, 0.0, 1.0);
}

const camera::TopViewFusion& SceneRenderer::Impl::Fusion(int k, int l) const {
  LazyFusion& lazy = *fusions[static_cast<size_t>(k * Layouts() + l)];
  std::call_once(lazy.built, [&] {
    camera::TopViewOptions view = options.top_view;
    const int axis_layouts = static_cast<int>(options.seam_layouts.size());
    if (l < axis_layouts) {
      view.camera_priority_rad = options.seam_layouts[static_cast<size_t>(l)];
    } else {
      view.seam_style = camera::SeamStyle::kFootprintRays;
      view.seam_front_angle_rad = view.seam_rear_angle_rad =
          options.ray_seam_angles_rad[static_cast<size_t>(l - axis_layouts)];
    }
    lazy.fusion = std::make_unique<camera::TopViewFusion>(fusion_rigs[static_cast<size_t>(k)],
                                                          options.fisheye_names, view);
  });
  return *lazy.fusion;
}

// The fisheye pixels that the exact fusion samples, widened by the largest
// blur and calibration error, so that a scene renders only those.
void SceneRenderer::Impl::MarkNeeded() {
  const int size = options.top_view.size_px;
  for (size_t c = 0; c < fisheyes.size(); ++c) {
    CameraTable& t = fisheyes[c];
    t.needed = cv::Mat(t.height, t.width, CV_8U, cv::Scalar(0));
    const camera::CameraModel model(fisheye_configs[c].intrinsics);
    const Eigen::Isometry3d T_camera_vehicle = fisheye_configs[c].T_vehicle_camera.inverse();
    const int camera = static_cast<int>(c);
    const auto mark = [&](int l) {
      const camera::TopViewFusion& fusion = Fusion(0, l);
      for (int v = 0; v < size; ++v) {
        for (int u = 0; u < size; ++u) {
          if (fusion.PrimaryCamera(u, v) != camera && fusion.SecondaryCamera(u, v) != camera)
            continue;
          const Eigen::Vector2d g = fusion.PixelToVehicle(Eigen::Vector2d(u, v));
          const auto px = model.Project(T_camera_vehicle * Eigen::Vector3d(g.x(), g.y(), 0.0));
          if (!px) continue;
          t.needed.at<std::uint8_t>(static_cast<int>(px->y()), static_cast<int>(px->x())) = 255;
        }
      }
    };
    // Every seam layout of the exact calibration (the perturbed ones are
    // within the margin). The camera meters its exposure on what the
    // optical-axis layouts sample, so that adding straight layouts changes
    // no exposure.
    const int axis_layouts = static_cast<int>(options.seam_layouts.size());
    for (int l = 0; l < axis_layouts; ++l) mark(l);
    t.metered = t.needed.clone();
    for (int l = axis_layouts; l < Layouts(); ++l) mark(l);
    cv::dilate(t.needed, t.needed, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(25, 25)));
    int first = t.height, last = 0;
    for (int v = 0; v < t.height; ++v) {
      if (cv::countNonZero(t.needed.row(v)) > 0) {
        first = std::min(first, v);
        last = v + 1;
      }
    }
    t.needed_rows = first < last ? cv::Range(first, last) : cv::Range(0, 0);
    t.needed_pixels = {};
    const AzimuthIndex& all = t.all_pixels;
    for (size_t k = 0; k < all.pixel.size(); ++k) {
      if (t.needed.data[all.pixel[k]] != 0)
        t.needed_pixels.Add(all.azimuth[k], all.pixel[k], all.reach[k], all.floor_reach[k],
                            all.roofed_reach[k]);
    }
  }
}

namespace {

// The car's own body: bumpers and sills a little beyond the footprint the
// fusion masks (below the cameras, so that they hide the floor next to the
// car, as a real car's do), the body, and a cabin. A camera on a part's
// surface sees that part behind it, not along it.
//
// Below the front camera the bumper's middle juts 12 cm ahead of the lens
// and 12 cm below it (a lip, or the plate's mount), rounded in plan: the
// floor it hides from that camera is a dome ahead of the footprint, about
// 0.6 m deep and as wide as the car, as the car that recorded ps2.0 shows
// in its views (its size was read off the real views).
constexpr size_t kEgoLip = 3;         // EgoBody()'s part below the front camera
constexpr float kEgoLipShade = 0.5f;  // under the bonnet: darker than the body's faces

std::vector<Solid> EgoBody() {
  std::vector<Solid> body(4);
  body[kEgoLip].shape = SolidShape::kCylinder;
  body[kEgoLip].center = Eigen::Vector2d(3.62, 0.0);
  body[kEgoLip].half_x = 0.2;
  body[kEgoLip].z0 = 0.25;
  body[kEgoLip].z1 = 0.48;
  body[0].center = Eigen::Vector2d(1.35, 0.0);
  body[0].half_x = 2.35 + 0.04;
  body[0].half_y = 0.925 + 0.04;
  body[0].z0 = 0.25;
  body[0].z1 = 0.45;
  body[1].center = Eigen::Vector2d(1.35, 0.0);
  body[1].half_x = 2.35;
  body[1].half_y = 0.925;
  body[1].z0 = 0.45;
  body[1].z1 = 0.9;
  body[2].center = Eigen::Vector2d(1.4, 0.0);
  body[2].half_x = 1.25;
  body[2].half_y = 0.8;
  body[2].z0 = 0.9;
  body[2].z1 = 1.45;
  return body;
}

// A camera's pixels within its image circle: their unit rays (camera
// frame) and angles off the axis.
struct PixelRays {
  std::vector<Eigen::Vector3d> rays;
  std::vector<double> off_axis;
  std::vector<bool> valid;
  double max_off = 1e-6;
};

PixelRays UnprojectPixels(const camera::CameraModel& model, int width, int height) {
  const size_t n = static_cast<size_t>(width) * static_cast<size_t>(height);
  PixelRays r;
  r.off_axis.assign(n, 0.0);
  r.rays.resize(n);
  r.valid.assign(n, false);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const size_t i = static_cast<size_t>(v) * static_cast<size_t>(width) + static_cast<size_t>(u);
      const auto ray = model.Unproject(Eigen::Vector2d(u, v));
      if (!ray) continue;
      const double angle = std::acos(std::clamp(ray->normalized().z(), -1.0, 1.0));
      // A real fisheye's image circle ends at its field of view: black beyond.
      if (angle > kMaxOffAxisRad) continue;
      r.valid[i] = true;
      r.rays[i] = ray->normalized();
      r.off_axis[i] = angle;
      r.max_off = std::max(r.max_off, r.off_axis[i]);
    }
  }
  return r;
}

// The valid pixels sorted by the azimuth of their ray, with their reach.
void IndexByAzimuth(const std::vector<bool>& valid, CameraTable* t) {
  const size_t n = valid.size();
  std::vector<std::pair<float, int>> az;
  az.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    if (!valid[i]) continue;
    az.emplace_back(std::atan2(t->rays[i].y(), t->rays[i].x()), static_cast<int>(i));
  }
  std::sort(az.begin(), az.end());
  for (const auto& [a, i] : az) {
    const size_t k = static_cast<size_t>(i);
    const bool ego = t->kind.data[k] == kEgo;
    const float h = t->horizontal[k];
    t->all_pixels.Add(a, i, ego ? -1.0f : t->ground_t[k] * h, ego ? -1.0f : t->floor_t[k] * h,
                      ego ? -1.0f : t->roofed_t[k] * h);
  }
}

}  // namespace

// Where the floor point g (vehicle frame) lies in the atlas, at the level
// that suits a footprint of that size; (-10, -10) beyond the floor.
cv::Point2f SceneRenderer::Impl::AtlasPixel(const Eigen::Vector2d& g, double footprint) const {
  const double near_res = options.near_resolution_m;
  cv::Point2f atlas_px(-10, -10);
  const double nx = (g.x() - options.near_min_x_m) / near_res - 0.5;
  const double ny = (options.near_half_width_m - g.y()) / near_res - 0.5;
  const bool in_near = nx > 1 && ny > 1 && nx < atlas.near.width - 2 && ny < atlas.near.height - 2;
  const double fx = (g.x() + options.far_half_extent_m) / options.far_resolution_m - 0.5;
  const double fy = (options.far_half_extent_m - g.y()) / options.far_resolution_m - 0.5;
  const bool in_far = fx > 1 && fy > 1 && fx < atlas.far.width - 2 && fy < atlas.far.height - 2;
  if (in_near && footprint < kMaxFootprintNearM) {
    atlas_px =
        cv::Point2f(static_cast<float>(atlas.near.x + nx), static_cast<float>(atlas.near.y + ny));
  } else if (in_near) {
    atlas_px = cv::Point2f(static_cast<float>(atlas.mid.x + (nx + 0.5) / 2 - 0.5),
                           static_cast<float>(atlas.mid.y + (ny + 0.5) / 2 - 0.5));
  } else if (in_far) {
    atlas_px =
        cv::Point2f(static_cast<float>(atlas.far.x + fx), static_cast<float>(atlas.far.y + fy));
  }
  return atlas_px;
}

CameraTable SceneRenderer::Impl::BuildTable(const camera::CameraConfig& config) const {
  const camera::CameraModel model(config.intrinsics);
  CameraTable t;
  t.name = config.name;
  t.config = config;
  t.pixel_angle_rad = 1.0 / std::max(1.0, config.intrinsics.fx);
  t.width = model.width();
  t.height = model.height();
  t.c_vehicle = config.T_vehicle_camera.translation();
  const Eigen::Matrix3d R = config.T_vehicle_camera.linear();
  const size_t n = static_cast<size_t>(t.width) * static_cast<size_t>(t.height);
  t.rays.assign(n, Eigen::Vector3f::Zero());
  t.ground_t.assign(n, kInf);
  t.horizontal.assign(n, 0.0f);
  t.ground_xy.assign(n, Eigen::Vector2f::Zero());
  t.footprint.assign(n, 0.0f);
  t.floor_t.assign(n, kInf);
  t.kind = cv::Mat(t.height, t.width, CV_8U, cv::Scalar(kNone));
  t.vignette = cv::Mat(t.height, t.width, CV_32F, cv::Scalar(0));
  t.ego_shade = cv::Mat(t.height, t.width, CV_32F, cv::Scalar(0));
  cv::Mat map(t.height, t.width, CV_32FC2, cv::Scalar(-10, -10));
  const PixelRays pixels = UnprojectPixels(model, t.width, t.height);
  const double cz = t.c_vehicle.z();
  const std::vector<Solid> body = EgoBody();
  for (int v = 0; v < t.height; ++v) {
    for (int u = 0; u < t.width; ++u) {
      const size_t i =
          static_cast<size_t>(v) * static_cast<size_t>(t.width) + static_cast<size_t>(u);
      if (!pixels.valid[i]) continue;
      const Eigen::Vector3d d = R * pixels.rays[i];
      t.rays[i] = d.cast<float>();
      t.horizontal[i] = static_cast<float>(std::hypot(d.x(), d.y()));
      const double vig = pixels.off_axis[i] / pixels.max_off;
      t.vignette.at<float>(v, u) = static_cast<float>(vig * vig);
      std::uint8_t kind = kUp;
      if (d.z() < -1e-6) {
        const double s = cz / -d.z();
        const Eigen::Vector2d g = t.c_vehicle.head<2>() + s * d.head<2>();
        // The pixel's footprint on the floor: its angle times the distance,
        // stretched by the grazing angle.
        const double pixel_angle = 1.0 / std::max(1.0, config.intrinsics.fx);
        const double footprint = s * pixel_angle / std::sqrt(std::max(1e-3, -d.z()));
        const cv::Point2f atlas_px = AtlasPixel(g, footprint);
        t.footprint[i] = static_cast<float>(footprint);
        t.floor_t[i] = static_cast<float>(s);
        t.ground_xy[i] = g.cast<float>();
        kind = kFarGround;
        if (atlas_px.x >= 0) {
          kind = kGround;
          map.at<cv::Point2f>(v, u) = atlas_px;
          t.ground_t[i] = static_cast<float>(cz / -d.z());
        }
      }
      SolidHit hit;
      hit.t = t.ground_t[i];
      bool on_body = false;
      float shade = 1.0f;
      for (size_t k = 0; k < body.size(); ++k) {
        if (!Intersect(body[k], 1.0, 0.0, t.c_vehicle, t.rays[i], &hit)) continue;
        on_body = true;  // the nearest part so far
        shade = k == kEgoLip ? kEgoLipShade : 1.0f;
      }
      if (on_body) {
        kind = kEgo;
        t.ego_shade.at<float>(v, u) = shade * (0.55f + 0.45f * std::abs(hit.normal.dot(t.rays[i])));
      }
      t.kind.at<std::uint8_t>(v, u) = kind;
    }
  }
  cv::convertMaps(map, cv::noArray(), t.map_xy, t.map_frac, CV_16SC2);
  t.ego = t.kind == kEgo;
  const float up = static_cast<float>(options.ceiling_height_m - t.c_vehicle.z());
  t.roofed_t = t.floor_t;
  for (size_t i = 0; i < n; ++i) {
    if (t.rays[i].z() > 1e-6f) t.roofed_t[i] = up / t.rays[i].z();
  }
  IndexByAzimuth(pixels.valid, &t);
  return t;
}

namespace {

// Lamps mirrored in a glossy floor: where the reflection of each lamp meets
// the floor for this camera, an elongated highlight. A grid of
// kSpecularCellM cells centred on the camera; empty without gloss.
cv::Mat SpecularMap(const CameraTable& t, const Scene& scene, const LightMap& light) {
  const Lighting& l = scene.light;
  cv::Mat specular;
  const int spec_n = static_cast<int>(2 * kSpecularHalfExtentM / kSpecularCellM);
  if (l.outdoor || !(scene.floor.gloss > 0.05)) return specular;
  specular = cv::Mat(spec_n, spec_n, CV_32F, cv::Scalar(0));
  const double cz = t.c_vehicle.z(), h = l.lamp_height_m;
  const Eigen::Vector2d c = t.c_vehicle.head<2>();
  const double s = l.lamp_spacing_m;
  constexpr double kReachM = 9.0;  // lamps farther mirror beyond the top view
  // The camera in the lamp grid's axes.
  const Eigen::Vector2d ax(std::cos(l.lamp_grid_yaw_rad), std::sin(l.lamp_grid_yaw_rad));
  const Eigen::Vector2d ay(-ax.y(), ax.x());
  const double cu = c.dot(ax), cw = c.dot(ay);
  const double ou = l.lamp_offset.dot(ax), ow = l.lamp_offset.dot(ay);
  for (double gx = std::floor((cu - kReachM - ou) / s); gx <= (cu + kReachM - ou) / s; gx += 1) {
    for (double gy = std::floor((cw - kReachM - ow) / s); gy <= (cw + kReachM - ow) / s; gy += 1) {
      const Eigen::Vector2d lamp_centre = l.lamp_offset + ax * (gx * s) + ay * (gy * s);
      const double strength = 35.0 * scene.floor.gloss * light.At(lamp_centre.x(), lamp_centre.y());
      // A tube 1.2 m along x: its reflection, three blobs along it, each
      // stretched towards the camera by the grazing view.
      for (const double along_tube : {-0.45, 0.0, 0.45}) {
        const Eigen::Vector2d lamp = lamp_centre + ax * along_tube;
        const Eigen::Vector2d r = c + (lamp - c) * (cz / (cz + h));
        const double dist = (r - c).norm();
        const Eigen::Vector2d away =
            dist > 1e-3 ? Eigen::Vector2d((r - c) / dist) : Eigen::Vector2d::UnitX();
        const double along = std::min(1.5, 0.25 + 0.35 * dist),
                     across = std::min(0.3, 0.08 + 0.04 * dist);
        const int cx = static_cast<int>((r.x() - c.x() + kSpecularHalfExtentM) / kSpecularCellM);
        const int cy = static_cast<int>((kSpecularHalfExtentM - (r.y() - c.y())) / kSpecularCellM);
        const int rad = static_cast<int>(std::ceil(3 * along / kSpecularCellM));
        for (int y = std::max(0, cy - rad); y < std::min(spec_n, cy + rad); ++y) {
          for (int x = std::max(0, cx - rad); x < std::min(spec_n, cx + rad); ++x) {
            const Eigen::Vector2d p(c.x() - kSpecularHalfExtentM + (x + 0.5) * kSpecularCellM,
                                    c.y() + kSpecularHalfExtentM - (y + 0.5) * kSpecularCellM);
            const Eigen::Vector2d dp = p - r;
            const double a = dp.dot(away) / along,
                         b = (dp.x() * away.y() - dp.y() * away.x()) / across;
            const double q = a * a + b * b;
            if (q < 16.0)
              specular.at<float>(y, x) += static_cast<float>(strength * std::exp(-0.5 * q));
          }
        }
      }
    }
  }
  return specular;
}

// What a ray that meets no floor sees: outdoors the sky, trees or a
// building; indoors the ceiling with its lamps, or the dark below the
// horizon.
inline cv::Vec3f SkyOrCeiling(const Eigen::Vector3f& d, const Lighting& l, const LightMap& light,
                              double ceiling, const Eigen::Vector3d& c_vehicle, float light_here,
                              const Eigen::Vector2d& grid_x) {
  const Colour tint = l.tint;
  cv::Vec3f p;
  if (l.outdoor) {
    const float up = std::max(0.0f, d.z());
    const float azimuth = std::atan2(d.y(), d.x());
    const float skyline = SkylineElevation(l.seed, azimuth);
    if (std::asin(std::clamp(d.z(), -1.0f, 1.0f)) < std::abs(skyline)) {
      // Trees (skyline > 0) or a building (< 0) against the sky.
      const std::uint64_t leaf =
          MixSeed(static_cast<std::uint64_t>(std::lround(azimuth * 150.0f)) * 1000 +
                      static_cast<std::uint64_t>(std::lround(up * 150.0f)),
                  l.seed);
      const float foliage = 0.6f + 0.8f * static_cast<float>(leaf % 1000) / 1000.0f;
      p = skyline > 0 ? cv::Vec3f(45, 85, 60) * foliage
                      : cv::Vec3f(150, 155, 160) * (std::sin(60.0f * up) > 0.6f ? 0.6f : 1.0f);
      p *= static_cast<float>(l.gain);
    } else {
      p = cv::Vec3f(250 - 30 * up, 235 - 40 * up, 225 - 60 * up) * static_cast<float>(l.gain);
    }
  } else if (d.z() > 0.02f) {
    const float s = static_cast<float>((ceiling - c_vehicle.z()) / d.z());
    const float x = static_cast<float>(c_vehicle.x()) + s * d.x();
    const float y = static_cast<float>(c_vehicle.y()) + s * d.y();
    const double ls = l.lamp_spacing_m;
    // The point in the lamp grid's axes (grid_x: its first axis).
    const double rx = x - l.lamp_offset.x(), ry = y - l.lamp_offset.y();
    const double gu = rx * grid_x.x() + ry * grid_x.y(), gw = ry * grid_x.x() - rx * grid_x.y();
    const double lx = gu - std::round(gu / ls) * ls;
    const double ly = gw - std::round(gw / ls) * ls;
    const bool lamp = std::abs(lx) < 0.6 && std::abs(ly) < 0.08;
    const float level = lamp ? 480.0f : 55.0f * light.At(x, y);
    p = cv::Vec3f(level * tint[0], level * tint[1], level * tint[2]);
  } else {
    const float level = 45.0f * light_here;
    p = cv::Vec3f(level, level, level);
  }
  return p;
}

// Where a solid can appear from a camera at c2: the wedge of azimuths
// [lo, hi] (every azimuth when `all`) and the nearest horizontal distance,
// inside which no ray meets it.
struct SolidWedge {
  float lo = 0.0f, hi = 0.0f, near_xy = 0.0f;
  bool all = false;
};

SolidWedge WedgeOf(const Solid& solid, const SolidFrame& frame, const Eigen::Vector2d& c2) {
  // The solid's footprint corners (or its circle's bounding square) seen
  // from the camera.
  std::vector<Eigen::Vector2d> corners;
  if (solid.shape == SolidShape::kBox) {
    const Eigen::Vector2d ax(frame.cos_yaw, frame.sin_yaw), ay(-ax.y(), ax.x());
    for (int sx = -1; sx <= 1; sx += 2) {
      for (int sy = -1; sy <= 1; sy += 2)
        corners.push_back(solid.center + ax * (sx * solid.half_x) + ay * (sy * solid.half_y));
    }
  } else {
    for (int sx = -1; sx <= 1; sx += 2) {
      for (int sy = -1; sy <= 1; sy += 2)
        corners.push_back(solid.center + Eigen::Vector2d(sx, sy) * solid.half_x);
    }
  }
  const Eigen::Vector2d to = solid.center - c2;
  const double centre = std::atan2(to.y(), to.x());
  double spread_lo = 0.0, spread_hi = 0.0, nearest = 1e9;
  bool all = false;
  for (size_t k = 0; k < corners.size(); ++k) {
    const Eigen::Vector2d a = corners[k] - c2, b = corners[(k + 1) % corners.size()] - c2;
    const double rel = AngleDiff(std::atan2(a.y(), a.x()), centre);
    spread_lo = std::min(spread_lo, rel);
    spread_hi = std::max(spread_hi, rel);
    // Distance from the camera to the edge a-b.
    const Eigen::Vector2d ab = b - a;
    const double u = std::clamp(-a.dot(ab) / std::max(1e-12, ab.squaredNorm()), 0.0, 1.0);
    nearest = std::min(nearest, (a + u * ab).norm());
  }
  // Inside the footprint, or a wedge of half a turn or more: every azimuth.
  const Eigen::Vector2d camera_local = frame.Local(solid, c2);
  if (spread_hi - spread_lo > 0.95 * kPi ||
      (solid.shape == SolidShape::kBox && std::abs(camera_local.x()) < solid.half_x &&
       std::abs(camera_local.y()) < solid.half_y)) {
    all = true;
    nearest = 0.0;
  }
  SolidWedge w;
  w.lo = static_cast<float>(centre + spread_lo - 0.01);
  w.hi = static_cast<float>(centre + spread_hi + 0.01);
  w.near_xy = static_cast<float>(nearest);
  w.all = all;
  return w;
}

// Solid s against the pixels of `index` in its azimuth wedge: where it is
// nearer than depth, depth becomes its distance and which becomes s.
void TraceSolid(const CameraTable& t, const AzimuthIndex& index, const std::vector<float>& reach,
                const Solid& solid, const SolidFrame& frame, size_t s,
                std::vector<float>* depth_out, std::vector<std::int16_t>* which_out) {
  std::vector<float>& depth = *depth_out;
  std::vector<std::int16_t>& which = *which_out;
  const SolidWedge wedge = WedgeOf(solid, frame, t.c_vehicle.head<2>());
  const float lo = wedge.lo, hi = wedge.hi;
  const float near_xy = wedge.near_xy;
  const float cz = static_cast<float>(t.c_vehicle.z()), top = static_cast<float>(solid.z1);
  const auto scan = [&](float a0, float a1) {
    const auto first = std::lower_bound(index.azimuth.begin(), index.azimuth.end(), a0);
    const auto last = std::upper_bound(index.azimuth.begin(), index.azimuth.end(), a1);
    const size_t k0 = static_cast<size_t>(first - index.azimuth.begin());
    const size_t k1 = static_cast<size_t>(last - index.azimuth.begin());
    for (size_t k = k0; k < k1; ++k) {
      // Rays that meet the floor (or the car) before the solid's nearest
      // point cannot meet it: read in azimuth order, contiguous.
      if (reach[k] < near_xy) continue;
      const size_t i = static_cast<size_t>(index.pixel[k]);
      if (depth[i] * t.horizontal[i] < near_xy) continue;
      // A rising ray above the solid's top where it comes nearest passes
      // over it (every solid is a vertical prism within [z0, z1]).
      const float dz = t.rays[i].z();
      if (dz > 0.0f && cz + near_xy * dz / std::max(1e-6f, t.horizontal[i]) > top) continue;
      SolidHit hit;
      hit.t = depth[i];
      if (Intersect(solid, frame.cos_yaw, frame.sin_yaw, t.c_vehicle, t.rays[i], &hit)) {
        depth[i] = hit.t;
        which[i] = static_cast<std::int16_t>(s);
      }
    }
  };
  if (wedge.all) {
    scan(-static_cast<float>(kPi) - 1, static_cast<float>(kPi) + 1);
  } else {
    const float pi = static_cast<float>(kPi);
    if (lo < -pi) {
      scan(lo + 2 * pi, pi + 1);
      scan(-pi - 1, hi);
    } else if (hi > pi) {
      scan(lo, pi + 1);
      scan(-pi - 1, hi - 2 * pi);
    } else {
      scan(lo, hi);
    }
  }
}

// A solid's colour where a ray hit it (p, local: the point in the map and
// in the solid's frame; facing: |cos| of the angle to the normal).
Colour SolidAlbedo(const Solid& solid, const SolidFrame& frame, const SolidHit& hit,
                   const Eigen::Vector3f& p, const Eigen::Vector2d& local, float facing) {
  Colour albedo = solid.colour;
  switch (solid.material) {
    case SolidMaterial::kPaint: {
      // A car body: a sill in shadow, a highlight along the shoulder,
      // lamps at the corners of its ends, a sheen at grazing angles.
      albedo *= 0.6f + 0.4f * facing + (hit.top ? 0.15f : 0.0f);
      // Sides darken downwards (they face the floor's dark, not the sky).
      if (!hit.top)
        albedo *= 0.75f + 0.35f * static_cast<float>((p.z() - solid.z0) / (solid.z1 - solid.z0));
      const double lx = local.x(), ly = local.y();
      if (!hit.top) {
        if (p.z() < solid.z0 + 0.15) albedo *= 0.55f;
        if (p.z() > solid.z1 - 0.07) albedo *= 1.25f;
        const bool end = std::abs(std::abs(lx) - solid.half_x) < 0.02;
        if (end && std::abs(ly) > solid.half_y - 0.35 && p.z() > solid.z1 - 0.25) {
          albedo = lx > 0 ? Colour(215, 225, 230) : Colour(40, 40, 190);
        }
      }
      albedo += Colour(35, 35, 35) * (1.0f - facing);
      break;
    }
    case SolidMaterial::kGlass:
      // Glass mirrors the bright sky or ceiling above at grazing angles.
      if (!hit.top) {
        const float up = static_cast<float>((p.z() - solid.z0) / (solid.z1 - solid.z0));
        albedo = Colour(45, 42, 40) * (1.0f + 1.2f * (1.0f - facing)) + Colour(30, 30, 28) * up;
      }
      break;
    case SolidMaterial::kTyre: {
      // A rim on each sidewall.
      const bool sidewall =
          std::abs(hit.normal.x() * -frame.sin_yaw + hit.normal.y() * frame.cos_yaw) > 0.9;
      const double r = std::hypot(local.x(), p.z() - (solid.z0 + solid.z1) / 2);
      if (sidewall && r < 0.19) albedo = r < 0.05 ? Colour(90, 90, 95) : Colour(165, 168, 172);
      albedo *= 0.7f + 0.3f * facing;
      break;
    }
    case SolidMaterial::kMatt:
    case SolidMaterial::kSkin:
      albedo *= 0.65f + 0.35f * facing;
      break;
  }
  if (solid.stripes) {
    if (solid.shape == SolidShape::kCone) {
      const double f = (p.z() - solid.z0) / (solid.z1 - solid.z0);
      if (f > 0.45 && f < 0.7) albedo = Colour(235, 235, 235);
    } else if (p.z() < 1.0 && !hit.top) {
      const bool dark = static_cast<int>(std::floor((p.x() + p.y() + p.z()) / 0.2)) % 2 == 0;
      albedo = dark ? Colour(35, 35, 35) : Colour(30, 190, 230);
    }
  }
  return albedo;
}

// Auto exposure: each camera meters its own image (every 7th pixel), so the
// four differ where they see different things (visible seams).
// protect_highlights: as a camera's exposure does, also keep the brightest
// 2 % of the metered pixels below white (a lot's bright walls and tags,
// which would otherwise clip, and a clipped tag's corners shrink it).
float AutoGain(const CameraTable& t, const cv::Mat& radiance, bool protect_highlights) {
  const size_t n = t.rays.size();
  double sum = 0.0;
  int count = 0;
  std::vector<float> lumas;
  const cv::Vec3f* px = radiance.ptr<cv::Vec3f>(0);
  for (size_t i = 0; i < n; i += 7) {
    if (t.kind.data[i] == kNone || (!t.metered.empty() && t.metered.data[i] == 0)) continue;
    const float luma = Luma(px[i]);
    sum += luma;
    ++count;
    if (protect_highlights) lumas.push_back(luma);
  }
  const float metered = count > 0 ? static_cast<float>(sum / count) : kAutoExposureTarget;
  float gain = kAutoExposureTarget / std::max(1.0f, metered);
  if (protect_highlights && !lumas.empty()) {
    const auto p98 = lumas.begin() + static_cast<long>(0.98 * static_cast<double>(lumas.size()));
    std::nth_element(lumas.begin(), p98, lumas.end());
    gain = std::min(gain, kHighlightLevel / std::max(1.0f, *p98));
  }
  return std::clamp(gain, 0.3f, 4.0f);
}

}  // namespace

// The floor, the sky or ceiling, and the car's body, within rows (the
// pixels the top view does not need black when need is given).
void SceneRenderer::Impl::ShadeBackground(const CameraTable& t, const Scene& scene,
                                          const LightMap& light, const Colour& ego_colour,
                                          const cv::Mat& ground, const cv::Mat& specular,
                                          const std::uint8_t* need, const cv::Range& rows,
                                          bool far_floor, cv::Mat* radiance) const {
  const Lighting& l = scene.light;
  const Eigen::Vector2d grid_x(std::cos(l.lamp_grid_yaw_rad), std::sin(l.lamp_grid_yaw_rad));
  const float light_here = light.At(t.c_vehicle.x(), t.c_vehicle.y());
  const Colour tint = l.tint;
  const int spec_n = static_cast<int>(2 * kSpecularHalfExtentM / kSpecularCellM);
  const double ceiling = options.ceiling_height_m;
  for (int v = rows.start; v < rows.end; ++v) {
    const std::uint8_t* kind = t.kind.ptr<std::uint8_t>(v);
    const cv::Vec3b* g = ground.ptr<cv::Vec3b>(v);
    cv::Vec3f* out = radiance->ptr<cv::Vec3f>(v);
    const float* ego = t.ego_shade.ptr<float>(v);
    for (int u = 0; u < t.width; ++u) {
      const size_t i =
          static_cast<size_t>(v) * static_cast<size_t>(t.width) + static_cast<size_t>(u);
      cv::Vec3f& p = out[u];
      if (need != nullptr && need[i] == 0) {
        p = cv::Vec3f(0, 0, 0);
        continue;
      }
      std::uint8_t k_here = kind[u];
      if (k_here == kFarGround) k_here = far_floor ? kGround : kUp;
      switch (k_here) {
        case kGround: {
          for (int k = 0; k < 3; ++k) p[k] = g[u][k] * kRadianceScale;
          if (!specular.empty()) {
            const Eigen::Vector2f gp = t.ground_xy[i];
            const int x = static_cast<int>((gp.x() - t.c_vehicle.x() + kSpecularHalfExtentM) /
                                           kSpecularCellM);
            const int y = static_cast<int>((kSpecularHalfExtentM - (gp.y() - t.c_vehicle.y())) /
                                           kSpecularCellM);
            if (x >= 0 && y >= 0 && x < spec_n && y < spec_n) {
              const float add = specular.at<float>(y, x);
              for (int k = 0; k < 3; ++k) p[k] += add * tint[k];
            }
          }
          break;
        }
        case kUp:
          p = SkyOrCeiling(t.rays[i], l, light, ceiling, t.c_vehicle, light_here, grid_x);
          break;
        case kEgo: {
          const float shade = ego[u] * light_here;
          for (int k = 0; k < 3; ++k) p[k] = ego_colour[k] * shade * tint[k];
          break;
        }
        default:
          p = cv::Vec3f(0, 0, 0);
      }
    }
  }
}

// The solids, each in the azimuth wedge it covers, over the background.
void SceneRenderer::Impl::ShadeSolids(const CameraTable& t, const Scene& scene,
                                      const LightMap& light, const std::uint8_t* need,
                                      cv::Mat* radiance, cv::Mat* solid_mask,
                                      const std::vector<float>* initial_depth) const {
  const Lighting& l = scene.light;
  const Colour tint = l.tint;
  const Eigen::Vector3f sun(
      static_cast<float>(std::cos(l.sun_azimuth_rad) * std::cos(l.sun_elevation_rad)),
      static_cast<float>(std::sin(l.sun_azimuth_rad) * std::cos(l.sun_elevation_rad)),
      static_cast<float>(std::sin(l.sun_elevation_rad)));
  const size_t n = t.rays.size();
  std::vector<float> depth(initial_depth != nullptr ? *initial_depth : t.ground_t);
  std::vector<std::int16_t> which(n, -1);
  std::vector<SolidFrame> frames;
  frames.reserve(scene.solids.size());
  for (const Solid& solid : scene.solids) frames.emplace_back(solid);
  const AzimuthIndex& index = need != nullptr ? t.needed_pixels : t.all_pixels;
  // On a lot's floor (initial_depth given) the floor, and indoors the
  // ceiling, end the rays.
  const std::vector<float>& reach = initial_depth == nullptr ? index.reach
                                    : scene.light.outdoor    ? index.floor_reach
                                                             : index.roofed_reach;
  // Nearest first: a pixel that already met something nearer than a
  // solid's nearest point skips it at once (a lot's far walls).
  std::vector<std::pair<double, size_t>> order;
  order.reserve(scene.solids.size());
  for (size_t s = 0; s < scene.solids.size(); ++s) {
    const Solid& solid = scene.solids[s];
    order.emplace_back(
        (solid.center - t.c_vehicle.head<2>()).norm() - std::hypot(solid.half_x, solid.half_y), s);
  }
  std::sort(order.begin(), order.end());
  for (const auto& [unused, s] : order) {
    TraceSolid(t, index, reach, scene.solids[s], frames[s], s, &depth, &which);
  }
  // The car's own body hides the floor as any solid does.
  if (solid_mask != nullptr) *solid_mask = t.ego.clone();
  for (size_t i = 0; i < n; ++i) {
    if (which[i] < 0) continue;
    const Solid& solid = scene.solids[static_cast<size_t>(which[i])];
    const SolidFrame& frame = frames[static_cast<size_t>(which[i])];
    SolidHit hit;
    Intersect(solid, frame.cos_yaw, frame.sin_yaw, t.c_vehicle, t.rays[i], &hit);
    const Eigen::Vector3f p = t.c_vehicle.cast<float>() + t.rays[i] * hit.t;
    const Eigen::Vector2d local = frame.Local(solid, p.head<2>().cast<double>());
    const float facing = std::abs(hit.normal.dot(t.rays[i]));
    float lit = light.At(p.x(), p.y());
    if (l.outdoor) lit *= 0.55f + 0.6f * std::max(0.0f, hit.normal.dot(sun));
    const Colour albedo = SolidAlbedo(solid, frame, hit, p, local, facing);
    cv::Vec3f& out =
        radiance->at<cv::Vec3f>(static_cast<int>(i) / t.width, static_cast<int>(i) % t.width);
    for (int k = 0; k < 3; ++k) out[k] = albedo[k] * lit * tint[k];
    if (solid_mask != nullptr) solid_mask->data[i] = 255;
  }
}

cv::Mat SceneRenderer::Impl::RenderCamera(const CameraTable& t, const Scene& scene,
                                          const CameraLook& look, const cv::Mat& atlas_bgr,
                                          const LightMap& light, const Colour& ego_colour,
                                          bool full, cv::Mat* solid_mask,
                                          const cv::Mat* floor_map) const {
  const std::uint8_t* need = full || t.needed.empty() ? nullptr : t.needed.data;
  cv::Mat ground;
  const cv::Range rows = need != nullptr ? t.needed_rows : cv::Range(0, t.height);
  ground = cv::Mat(t.height, t.width, CV_8UC3);  // read only within rows
  if (rows.size() > 0) {
    cv::Mat band = ground.rowRange(rows);
    if (floor_map != nullptr) {
      cv::remap(atlas_bgr, band, floor_map->rowRange(rows), cv::noArray(), cv::INTER_LINEAR,
                cv::BORDER_CONSTANT);
    } else {
      cv::remap(atlas_bgr, band, t.map_xy.rowRange(rows), t.map_frac.rowRange(rows),
                cv::INTER_LINEAR, cv::BORDER_CONSTANT);
    }
  }
  const cv::Mat specular = SpecularMap(t, scene, light);

  // Every pixel within rows is written below; only the others need zeros.
  cv::Mat radiance(t.height, t.width, CV_32FC3);
  radiance.rowRange(0, rows.start).setTo(cv::Scalar::all(0));
  radiance.rowRange(rows.end, t.height).setTo(cv::Scalar::all(0));
  ShadeBackground(t, scene, light, ego_colour, ground, specular, need, rows, floor_map != nullptr,
                  &radiance);
  if (floor_map != nullptr) {
    // On a lot's floor: the floor wherever it is (indoors under the
    // ceiling), then the tags, nearer.
    std::vector<float> depth = scene.light.outdoor ? t.floor_t : t.roofed_t;
    if (!scene.tags.empty()) ShadeTags(t, scene, light, &radiance, &depth);
    ShadeSolids(t, scene, light, need, &radiance, solid_mask, &depth);
  } else {
    ShadeSolids(t, scene, light, need, &radiance, solid_mask);
  }
  const float auto_gain = AutoGain(t, radiance, floor_map != nullptr);
  cv::Mat out8;
  ApplyLook(look, t, auto_gain, full, &radiance, &out8);
  return out8;
}

const std::array<cv::Mat, 5>& SceneRenderer::Impl::TagTexture(int tag_id) const {
  const std::lock_guard<std::mutex> lock(tag_mutex);
  auto it = tag_textures.find(tag_id);
  if (it == tag_textures.end()) {
    std::array<cv::Mat, 5> levels;
    levels[0] = Tag36h11Image(tag_id, 16);
    for (size_t l = 1; l < levels.size(); ++l) {
      cv::resize(levels[l - 1], levels[l], cv::Size(), 0.5, 0.5, cv::INTER_AREA);
    }
    it = tag_textures.emplace(tag_id, std::move(levels)).first;
  }
  return it->second;  // std::map: never moved by later insertions
}

cv::Mat SceneRenderer::Impl::FloorMap(const CameraTable& t, const FloorAtlas& floor, double yaw_rad,
                                      const Eigen::Vector2d& tr, bool full) const {
  cv::Mat map(t.height, t.width, CV_32FC2, cv::Scalar(-10, -10));
  const cv::Range rows = full || t.needed.empty() ? cv::Range(0, t.height) : t.needed_rows;
  const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
  for (int v = rows.start; v < rows.end; ++v) {
    const std::uint8_t* kind = t.kind.ptr<std::uint8_t>(v);
    const std::uint8_t* need = full || t.needed.empty() ? nullptr : t.needed.ptr<std::uint8_t>(v);
    cv::Point2f* out = map.ptr<cv::Point2f>(v);
    for (int u = 0; u < t.width; ++u) {
      if ((kind[u] != kGround && kind[u] != kFarGround) || (need != nullptr && need[u] == 0))
        continue;
      const size_t i =
          static_cast<size_t>(v) * static_cast<size_t>(t.width) + static_cast<size_t>(u);
      const Eigen::Vector2f& g = t.ground_xy[i];
      const Eigen::Vector2d p(c * g.x() - s * g.y() + tr.x(), s * g.x() + c * g.y() + tr.y());
      out[u] = floor.AtlasPixel(p, t.footprint[i]);
    }
  }
  return map;
}

namespace {

// Bilinear sample of an 8-bit grey image at (x, y), pixel centres at
// integers, clamped at the edges.
float SampleGrey(const cv::Mat& img, double x, double y) {
  const double cx = std::clamp(x, 0.0, img.cols - 1.001), cy = std::clamp(y, 0.0, img.rows - 1.001);
  const int x0 = static_cast<int>(cx), y0 = static_cast<int>(cy);
  const float fx = static_cast<float>(cx - x0), fy = static_cast<float>(cy - y0);
  const std::uint8_t* r0 = img.ptr<std::uint8_t>(y0);
  const std::uint8_t* r1 = img.ptr<std::uint8_t>(y0 + 1);
  return (r0[x0] * (1 - fx) + r0[x0 + 1] * fx) * (1 - fy) +
         (r1[x0] * (1 - fx) + r1[x0 + 1] * fx) * fy;
}

// A tag's paper: black and white as albedo, with a one-cell white margin
// round the tag's own white ring, as tags are printed and mounted.
constexpr float kTagBlack = 25.0f, kTagWhite = 215.0f;
constexpr double kTagMarginCells = 1.0;

}  // namespace

// Paper III-B: each tag a vertical square on its wall or pillar, ray cast
// over the pixels its corners project round.
void SceneRenderer::Impl::ShadeTags(const CameraTable& t, const Scene& scene, const LightMap& light,
                                    cv::Mat* radiance, std::vector<float>* depth) const {
  const camera::CameraModel model(t.config.intrinsics);
  const Eigen::Isometry3d T_camera_vehicle = t.config.T_vehicle_camera.inverse();
  const Colour tint = scene.light.tint;
  const Eigen::Vector3d c = t.c_vehicle;
  for (const WallTag& tag : scene.tags) {
    const Eigen::Vector3d n(std::cos(tag.normal_yaw_rad), std::sin(tag.normal_yaw_rad), 0.0);
    const Eigen::Vector3d right(-n.y(), n.x(), 0.0);  // the viewer's right, facing the tag
    const Eigen::Vector3d P(tag.center.x(), tag.center.y(), tag.z_center_m);
    if (n.dot(c - P) <= 0.0) continue;  // seen from behind its wall
    const double cell = tag.size_m / kTagBlackCells;
    const double half_cells = kTagTotalCells / 2.0 + kTagMarginCells;
    const double half = half_cells * cell;
    double u0 = 1e9, v0 = 1e9, u1 = -1e9, v1 = -1e9;
    bool whole = true;
    for (const double sx : {-1.0, 1.0}) {
      for (const double sz : {-1.0, 1.0}) {
        const Eigen::Vector3d q = P + right * (sx * half) + Eigen::Vector3d::UnitZ() * (sz * half);
        const auto px = model.Project(T_camera_vehicle * q);
        if (!px) {
          whole = false;
          continue;
        }
        u0 = std::min(u0, px->x());
        v0 = std::min(v0, px->y());
        u1 = std::max(u1, px->x());
        v1 = std::max(v1, px->y());
      }
    }
    // A tag partly behind the camera is left out (a front camera sees
    // tags ahead).
    if (!whole) continue;
    const int x0 = std::max(0, static_cast<int>(std::floor(u0)) - 2);
    const int y0 = std::max(0, static_cast<int>(std::floor(v0)) - 2);
    const int x1 = std::min(t.width, static_cast<int>(std::ceil(u1)) + 3);
    const int y1 = std::min(t.height, static_cast<int>(std::ceil(v1)) + 3);
    if (x0 >= x1 || y0 >= y1) continue;
    const std::array<cv::Mat, 5>& texture = TagTexture(tag.tag_id);
    for (int v = y0; v < y1; ++v) {
      cv::Vec3f* out = radiance->ptr<cv::Vec3f>(v);
      const std::uint8_t* kind = t.kind.ptr<std::uint8_t>(v);
      for (int u = x0; u < x1; ++u) {
        if (kind[u] == kNone || kind[u] == kEgo) continue;
        const size_t i =
            static_cast<size_t>(v) * static_cast<size_t>(t.width) + static_cast<size_t>(u);
        const Eigen::Vector3d d = t.rays[i].cast<double>();
        const double facing = n.dot(d);
        if (facing >= -1e-6) continue;
        const double along = n.dot(P - c) / facing;
        if (!(along > 0.0 && along < (*depth)[i])) continue;
        const Eigen::Vector3d q = c + d * along;
        const double a = (q - P).dot(right) / cell + kTagTotalCells / 2.0;
        const double b = (P.z() - q.z()) / cell + kTagTotalCells / 2.0;
        if (a < -kTagMarginCells || b < -kTagMarginCells || a > kTagTotalCells + kTagMarginCells ||
            b > kTagTotalCells + kTagMarginCells) {
          continue;
        }
        float texel = 255.0f;
        if (a >= 0.0 && b >= 0.0 && a < kTagTotalCells && b < kTagTotalCells) {
          // The level whose texel matches the pixel's footprint on the tag.
          const double footprint = along * t.pixel_angle_rad / std::max(-facing, 0.2);
          const double texel0 = cell / 16.0;
          const int level = std::clamp(
              static_cast<int>(std::floor(std::log2(std::max(1e-9, footprint / texel0)))), 0, 4);
          const double per_cell = 16.0 / static_cast<double>(1 << level);
          texel = SampleGrey(texture[static_cast<size_t>(level)], a * per_cell - 0.5,
                             b * per_cell - 0.5);
        }
        const float albedo = kTagBlack + (kTagWhite - kTagBlack) * texel / 255.0f;
        const float lit = albedo * light.At(q.x(), q.y());
        out[u] = cv::Vec3f(lit * tint[0], lit * tint[1], lit * tint[2]);
        (*depth)[i] = static_cast<float>(along);
      }
    }
  }
}

namespace {

// Dirt on the lens: blurred, brownish spots.
void AddDirt(const CameraLook& look, cv::RNG& rng, cv::Mat* image) {
  cv::Mat& img = *image;
  for (int s = 0; s < look.dirt_spots; ++s) {
    const int radius = static_cast<int>(rng.uniform(20.0, 70.0));
    const cv::Point centre(rng.uniform(0, img.cols), rng.uniform(0, img.rows));
    const cv::Rect roi = cv::Rect(centre.x - radius, centre.y - radius, 2 * radius, 2 * radius) &
                         cv::Rect(0, 0, img.cols, img.rows);
    if (roi.area() <= 0) continue;
    cv::Mat blurred;
    cv::GaussianBlur(img(roi), blurred, cv::Size(), radius / 3.0);
    const float strength = static_cast<float>(rng.uniform(0.4, 0.9));
    for (int r = 0; r < roi.height; ++r) {
      for (int c = 0; c < roi.width; ++c) {
        const float dx = static_cast<float>(roi.x + c - centre.x),
                    dy = static_cast<float>(roi.y + r - centre.y);
        const float a = strength * std::exp(-(dx * dx + dy * dy) / (0.35f * radius * radius));
        cv::Vec3f& p = img.at<cv::Vec3f>(roi.y + r, roi.x + c);
        const cv::Vec3f b = blurred.at<cv::Vec3f>(r, c);
        const cv::Vec3f dirt = b * 0.6f + cv::Vec3f(40, 55, 65);
        p = p * (1 - a) + dirt * a;
      }
    }
  }
}

// Glare from a light source in the upper part of the image.
void AddGlare(const CameraLook& look, cv::RNG& rng, cv::Mat* image) {
  cv::Mat& img = *image;
  const cv::Point2f centre(static_cast<float>(rng.uniform(0.2, 0.8) * img.cols),
                           static_cast<float>(rng.uniform(0.0, 0.3) * img.rows));
  const float radius = static_cast<float>(0.35 * img.cols);
  for (int r = 0; r < img.rows; ++r) {
    cv::Vec3f* row = img.ptr<cv::Vec3f>(r);
    for (int c = 0; c < img.cols; ++c) {
      const float dx = c - centre.x, dy = r - centre.y;
      const float add = static_cast<float>(look.glare) *
                        (220.0f * std::exp(-(dx * dx + dy * dy) / (radius * radius)) + 25.0f);
      row[c] += cv::Vec3f(add * 0.9f, add * 0.97f, add);
    }
  }
}

// The optics' blur on the 8-bit image: defocus, a coarser sensor, motion.
void BlurOptics(const CameraLook& look, cv::Mat* out8) {
  if (look.defocus_px > 0.3) cv::GaussianBlur(*out8, *out8, cv::Size(), look.defocus_px);
  if (look.sensor_scale < 0.98) {
    cv::Mat coarse;
    cv::resize(*out8, coarse, cv::Size(), look.sensor_scale, look.sensor_scale, cv::INTER_AREA);
    cv::resize(coarse, *out8, out8->size(), 0, 0, cv::INTER_LINEAR);
  }
  if (look.motion_blur_px >= 1.0) {
    const int len = static_cast<int>(std::ceil(look.motion_blur_px)) | 1;
    cv::Mat kernel(len, len, CV_32F, cv::Scalar(0));
    const cv::Point2f c(len / 2.0f, len / 2.0f);
    const cv::Point2f d(static_cast<float>(std::cos(look.motion_angle_rad) * len / 2.0),
                        static_cast<float>(std::sin(look.motion_angle_rad) * len / 2.0));
    cv::line(kernel, c - d, c + d, cv::Scalar(1.0), 1, cv::LINE_AA);
    kernel /= std::max(1e-6, cv::sum(kernel)[0]);
    cv::filter2D(*out8, *out8, -1, kernel);
  }
}

// Chroma noise: blue and red deviations drawn on a grid three pixels
// apart and interpolated (cubic), so that they come out as soft blotches a
// few pixels across; green takes back a third of their sum, keeping the
// brightness about where it was.
void AddChromaNoise(const CameraLook& look, cv::Mat* out8) {
  constexpr float kBlueShare = 1.4f;  // blue deviates more than red
  cv::RNG rng(MixSeed(look.seed, 0xc4));
  cv::Mat coarse(out8->rows / 3 + 2, out8->cols / 3 + 2, CV_32FC2);
  rng.fill(coarse, cv::RNG::NORMAL, 0.0, look.chroma_noise);
  cv::Mat fine;
  cv::resize(coarse, fine, out8->size(), 0, 0, cv::INTER_CUBIC);
  for (int r = 0; r < out8->rows; ++r) {
    cv::Vec3b* o = out8->ptr<cv::Vec3b>(r);
    const cv::Vec2f* n = fine.ptr<cv::Vec2f>(r);
    for (int c = 0; c < out8->cols; ++c) {
      if (o[c] == cv::Vec3b(0, 0, 0)) continue;  // not rendered
      const float blue = kBlueShare * n[c][0], red = n[c][1];
      o[c][0] = cv::saturate_cast<std::uint8_t>(o[c][0] + blue);
      o[c][1] = cv::saturate_cast<std::uint8_t>(o[c][1] - (blue + red) / 3.0f);
      o[c][2] = cv::saturate_cast<std::uint8_t>(o[c][2] + red);
    }
  }
}

}  // namespace

// Exposure, white balance and vignetting into 8 bits (light), and sensor
// noise from the noise bank (noise); either or both in one pass.
void SceneRenderer::Impl::Develop(const cv::Mat& img, const CameraTable& table,
                                  const DevelopParams& params, bool light, bool noise,
                                  cv::Mat* out8) const {
  const float gain[3] = {params.gain[0], params.gain[1], params.gain[2]};
  const float vig = params.vignetting;
  const int ox0 = params.ox0, oy0 = params.oy0, ox1 = params.ox1, ox2 = params.ox2;
  const float sigma = params.sigma;
  const bool masked = params.masked;
  for (int r = 0; r < img.rows; ++r) {
    const cv::Vec3f* in = img.ptr<cv::Vec3f>(r);
    const float* vrow = table.vignette.ptr<float>(r);
    cv::Vec3b* o = out8->ptr<cv::Vec3b>(r);
    const std::uint8_t* kind = table.kind.ptr<std::uint8_t>(r);
    const std::uint8_t* need = masked ? table.needed.ptr<std::uint8_t>(r) : nullptr;
    const float* n0 = noise_bank.ptr<float>((r + oy0) % kNoiseBankSize);
    int i0 = ox0, i1 = ox1, i2 = ox2;
    for (int c = 0; c < img.cols; ++c) {
      if (++i0 == kNoiseBankSize) i0 = 0;
      if (++i1 == kNoiseBankSize) i1 = 0;
      if (++i2 == kNoiseBankSize) i2 = 0;
      if (kind[c] == kNone || (need != nullptr && need[c] == 0)) {
        o[c] = cv::Vec3b(0, 0, 0);
        continue;
      }
      float v[3];
      if (light) {
        const float fall = 1.0f - vig * vrow[c];
        for (int k = 0; k < 3; ++k) v[k] = in[c][k] * gain[k] * fall;
      } else {
        for (int k = 0; k < 3; ++k) v[k] = o[c][k];
      }
      if (noise) {
        const float lum = sigma * n0[i0];
        v[0] += lum + 0.5f * sigma * n0[i1];
        v[1] += lum;
        v[2] += lum + 0.5f * sigma * n0[i2];
      }
      for (int k = 0; k < 3; ++k) o[c][k] = cv::saturate_cast<std::uint8_t>(v[k]);
    }
  }
}

// The camera: exposure, white balance, vignetting, defocus, motion blur,
// glare, a dirty lens, noise, chroma noise, and compression.
void SceneRenderer::Impl::ApplyLook(const CameraLook& look, const CameraTable& table,
                                    float auto_gain, bool full, cv::Mat* radiance,
                                    cv::Mat* out8) const {
  cv::Mat& img = *radiance;
  cv::RNG rng(MixSeed(look.seed, 0xca));
  AddDirt(look, rng, &img);
  if (look.glare > 0) AddGlare(look, rng, &img);
  // Exposure, white balance and vignetting into 8 bits; the optics' blur
  // (on 8 bits: four times cheaper than on radiance); then sensor noise.
  DevelopParams params;
  params.gain[0] = static_cast<float>(auto_gain * look.exposure * look.white_balance[0]);
  params.gain[1] = static_cast<float>(auto_gain * look.exposure * look.white_balance[1]);
  params.gain[2] = static_cast<float>(auto_gain * look.exposure * look.white_balance[2]);
  params.vignetting = static_cast<float>(look.vignetting);
  params.ox0 = rng.uniform(0, kNoiseBankSize);
  params.oy0 = rng.uniform(0, kNoiseBankSize);
  params.ox1 = rng.uniform(0, kNoiseBankSize);
  params.ox2 = rng.uniform(0, kNoiseBankSize);
  params.sigma = static_cast<float>(look.noise_sigma);
  params.masked = !full && !table.needed.empty();
  const bool blurred =
      look.defocus_px > 0.3 || look.motion_blur_px >= 1.0 || look.sensor_scale < 0.98;
  // Without blur, one pass does all; with it, the noise comes after.
  *out8 = cv::Mat(img.size(), CV_8UC3);
  Develop(img, table, params, true, !blurred, out8);
  BlurOptics(look, out8);
  if (blurred) Develop(img, table, params, false, true, out8);
  if (look.chroma_noise > 0) AddChromaNoise(look, out8);
  if (look.jpeg_quality < 95) {
    std::vector<std::uint8_t> bytes;
    cv::imencode(".jpg", *out8, bytes, {cv::IMWRITE_JPEG_QUALITY, look.jpeg_quality});
    *out8 = cv::imdecode(bytes, cv::IMREAD_COLOR);
  }
}

SceneRenderer::SceneRenderer(const camera::CameraRig& rig, const SceneRendererOptions& options)
    : impl_(std::make_unique<Impl>(rig, options)) {}
SceneRenderer::~SceneRenderer() = default;
SceneRenderer::SceneRenderer(SceneRenderer&&) noexcept = default;
SceneRenderer& SceneRenderer::operator=(SceneRenderer&&) noexcept = default;

void SceneRenderer::BuildFusions(int threads, bool straight_layouts) const {
  const Impl& m = *impl_;
  const int calibrations = static_cast<int>(m.fusion_rigs.size());
  const int layouts =
      straight_layouts ? m.Layouts() : static_cast<int>(m.options.seam_layouts.size());
  std::atomic<int> next{0};
  const auto work = [&] {
    for (int i = next++; i < calibrations * layouts; i = next++) m.Fusion(i / layouts, i % layouts);
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < std::max(1, threads); ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
}

const camera::TopViewFusion& SceneRenderer::FusionOf(const Scene& scene) const {
  const int calibrations = static_cast<int>(impl_->fusion_rigs.size());
  const int k = std::clamp(scene.fusion_calibration, 0, calibrations - 1);
  const int l = std::clamp(scene.fusion_seams, 0, impl_->Layouts() - 1);
  return impl_->Fusion(k, l);
}

const SceneRendererOptions& SceneRenderer::options() const { return impl_->options; }

cv::Mat SceneRenderer::Impl::FuseGrey(const camera::TopViewFusion& fusion, const cv::Mat& atlas8,
                                      const std::vector<cv::Mat>* hide) const {
  std::vector<cv::Mat> views;
  for (size_t c = 0; c < fisheyes.size(); ++c) {
    cv::Mat v;
    cv::remap(atlas8, v, fisheyes[c].map_xy, fisheyes[c].map_frac, cv::INTER_LINEAR,
              cv::BORDER_CONSTANT);
    cv::Mat on_ground = fisheyes[c].kind == kGround;
    v.setTo(0, ~on_ground);
    if (hide != nullptr && !(*hide)[c].empty()) v.setTo(0, (*hide)[c]);
    views.push_back(v);
  }
  return fusion.Fuse(views);
}

cv::Mat SceneRenderer::Impl::MarkDots(const camera::TopViewFusion& fusion, const Scene& scene,
                                      const Canvas& near, const Canvas& far) const {
  cv::Mat a8(atlas.size, CV_8UC1, cv::Scalar(0));
  const auto draw = [&](const Canvas& canvas, const cv::Rect& where) {
    cv::Mat level = a8(where);
    for (const MarkingPoint& mark : scene.marks) {
      const Eigen::Vector2d px = canvas.PixelOf(mark.p_vehicle);
      const int radius = std::max(4, static_cast<int>(0.02 / canvas.resolution_m * 16));
      cv::circle(level,
                 cv::Point(static_cast<int>(std::lround(px.x() * 16)),
                           static_cast<int>(std::lround(px.y() * 16))),
                 radius, cv::Scalar(255), -1, cv::LINE_AA, 4);
    }
  };
  draw(near, atlas.near);
  Canvas mid_level = near;
  mid_level.resolution_m = 2 * near.resolution_m;
  draw(mid_level, atlas.mid);
  draw(far, atlas.far);
  return FuseGrey(fusion, a8, nullptr);
}

namespace {

// The surround-view unit's own processing of its top view: sharpening and
// saturation.
void ProcessLikeTheUnit(const Scene& scene, cv::Mat* top) {
  if (scene.top_view_sharpen > 0) {
    cv::Mat blurred;
    cv::GaussianBlur(*top, blurred, cv::Size(), 1.2);
    cv::addWeighted(*top, 1.0 + scene.top_view_sharpen, blurred, -scene.top_view_sharpen, 0.0,
                    *top);
  }
  if (std::abs(scene.saturation - 1.0) <= 1e-3) return;
  const int sat = static_cast<int>(std::lround(scene.saturation * 256));
  for (int r = 0; r < top->rows; ++r) {
    cv::Vec3b* row = top->ptr<cv::Vec3b>(r);
    for (int c = 0; c < top->cols; ++c) {
      const int y = (29 * row[c][0] + 150 * row[c][1] + 77 * row[c][2]) >> 8;
      for (int k = 0; k < 3; ++k)
        row[c][k] = cv::saturate_cast<std::uint8_t>(y + (((row[c][k] - y) * sat) >> 8));
    }
  }
}

}  // namespace

RenderedScene SceneRenderer::Render(const Scene& scene, FontBook* fonts,
                                    const RenderRequest& request) const {
  const Impl& m = *impl_;
  const SceneRendererOptions& o = m.options;
  if (scene.cameras.size() < m.fisheyes.size()) {
    throw std::invalid_argument("scene renderer: the scene has " +
                                std::to_string(scene.cameras.size()) + " camera looks for " +
                                std::to_string(m.fisheyes.size()) + " cameras");
  }
  const LightMap light(scene.light);
  // The floor: near at full resolution, halved, and far.
  Canvas near(o.near_min_x_m, o.near_half_width_m, o.near_max_x_m - o.near_min_x_m,
              2 * o.near_half_width_m, o.near_resolution_m);
  cv::Mat slot_paint;
  PaintFloor(scene, light, {}, fonts, &near, request.slot_paint ? &slot_paint : nullptr);
  Canvas far(-o.far_half_extent_m, o.far_half_extent_m, 2 * o.far_half_extent_m,
             2 * o.far_half_extent_m, o.far_resolution_m);
  FloorPainterOptions far_options;
  far_options.draw_text = false;
  cv::Mat far_slot_paint;
  PaintFloor(scene, light, far_options, nullptr, &far,
             request.slot_paint ? &far_slot_paint : nullptr);
  // Where they overlap the far floor is the near one, shrunk: no seam.
  const cv::Rect near_in_far = m.NearInFar();
  if (near_in_far.area() > 0) {
    cv::resize(near.bgr, far.bgr(near_in_far), near_in_far.size(), 0, 0, cv::INTER_AREA);
  }
  const cv::Mat atlas = m.Stack(near.bgr, far.bgr);

  Random ego_rng = Random::Derive(scene.seed, 0xe90);
  const float ego_level = static_cast<float>(ego_rng.Uniform(20, 200));
  const Colour ego_colour(ego_level, ego_level,
                          ego_level * static_cast<float>(ego_rng.Uniform(0.9, 1.1)));

  RenderedScene out;
  std::vector<cv::Mat> solid_masks(m.fisheyes.size());
  for (size_t c = 0; c < m.fisheyes.size(); ++c) {
    out.fisheyes.push_back(m.RenderCamera(m.fisheyes[c], scene, scene.cameras[c], atlas, light,
                                          ego_colour, request.fisheyes,
                                          request.solids ? &solid_masks[c] : nullptr));
  }
  const camera::TopViewFusion& fusion = FusionOf(scene);
  cv::Mat top = fusion.Fuse(out.fisheyes, scene.fusion_nearest ? camera::FusionLookup::kNearest
                                                               : camera::FusionLookup::kBilinear);
  ProcessLikeTheUnit(scene, &top);
  out.top_view = top;
  if (request.front && m.front) {
    out.front = m.RenderCamera(*m.front, scene, scene.front_camera, atlas, light, ego_colour, true,
                               nullptr);
  }
  if (request.slot_paint) {
    out.slot_paint = m.FuseGrey(fusion, m.Stack(slot_paint, far_slot_paint),
                                request.solids ? &solid_masks : nullptr);
  }
  if (request.solids) {
    std::vector<cv::Mat> masks = solid_masks;
    out.solids = fusion.Fuse(masks);
  }
  if (request.dots) out.dots = m.MarkDots(fusion, scene, near, far);
  return out;
}

RenderedScene SceneRenderer::RenderOnFloor(const Scene& view, const LightMap& light,
                                           const FloorAtlas& floor, double yaw_rad,
                                           const Eigen::Vector2d& t,
                                           const RenderRequest& request) const {
  const Impl& m = *impl_;
  if (view.cameras.size() < m.fisheyes.size()) {
    throw std::invalid_argument("scene renderer: the view has " +
                                std::to_string(view.cameras.size()) + " camera looks for " +
                                std::to_string(m.fisheyes.size()) + " cameras");
  }
  Random ego_rng = Random::Derive(view.seed, 0xe90);
  const float ego_level = static_cast<float>(ego_rng.Uniform(20, 200));
  const Colour ego_colour(ego_level, ego_level,
                          ego_level * static_cast<float>(ego_rng.Uniform(0.9, 1.1)));
  RenderedScene out;
  // The front camera (the largest image) on a thread of its own, beside
  // the fisheyes.
  // (A future joins however this function is left, and carries the
  // thread's exception.)
  std::future<cv::Mat> front;
  if (request.front && m.front) {
    front = std::async(std::launch::async, [&] {
      const cv::Mat floor_map = m.FloorMap(*m.front, floor, yaw_rad, t, true);
      return m.RenderCamera(*m.front, view, view.front_camera, floor.bgr, light, ego_colour, true,
                            nullptr, &floor_map);
    });
  }
  for (size_t c = 0; c < m.fisheyes.size(); ++c) {
    const cv::Mat floor_map = m.FloorMap(m.fisheyes[c], floor, yaw_rad, t, request.fisheyes);
    out.fisheyes.push_back(m.RenderCamera(m.fisheyes[c], view, view.cameras[c], floor.bgr, light,
                                          ego_colour, request.fisheyes, nullptr, &floor_map));
  }
  if (front.valid()) out.front = front.get();
  if (request.top_view) {
    cv::Mat top =
        FusionOf(view).Fuse(out.fisheyes, view.fusion_nearest ? camera::FusionLookup::kNearest
                                                              : camera::FusionLookup::kBilinear);
    ProcessLikeTheUnit(view, &top);
    out.top_view = top;
  }
  return out;
}

std::optional<Eigen::Vector2d> SceneRenderer::FusedPixelOf(const Scene& scene,
                                                           const Eigen::Vector2d& p_vehicle) const {
  const Impl& m = *impl_;
  const camera::TopViewFusion& fusion = FusionOf(scene);
  const camera::CameraRig& fusion_rig = m.fusion_rigs[static_cast<size_t>(
      std::clamp(scene.fusion_calibration, 0, static_cast<int>(m.fusion_rigs.size()) - 1))];
  const Eigen::Vector3d P(p_vehicle.x(), p_vehicle.y(), 0.0);
  // Where camera c shows P in the fusion: the true camera sees P at a pixel;
  // the fusion, believing its own extrinsics, puts that pixel's ground
  // point at this top-view pixel.
  const auto through = [&](int c) -> std::optional<Eigen::Vector2d> {
    const camera::CameraConfig& truth = m.fisheye_configs[static_cast<size_t>(c)];
    const camera::CameraModel& model = m.fisheye_models[static_cast<size_t>(c)];
    const auto pixel = model.Project(truth.T_vehicle_camera.inverse() * P);
    const camera::CameraConfig* assumed = fusion_rig.Find(truth.name);
    if (!pixel || assumed == nullptr) return std::nullopt;
    const auto ray = model.Unproject(*pixel);
    if (!ray) return std::nullopt;
    const Eigen::Vector3d d = assumed->T_vehicle_camera.linear() * *ray;
    const Eigen::Vector3d o = assumed->T_vehicle_camera.translation();
    if (d.z() >= -1e-9) return std::nullopt;
    return fusion.VehicleToPixel((o + d * (o.z() / -d.z())).head<2>());
  };
  const auto round = [](const Eigen::Vector2d& q) {
    return std::pair<int, int>(static_cast<int>(std::lround(q.x())),
                               static_cast<int>(std::lround(q.y())));
  };
  // The camera the fusion uses there depends on where "there" is: iterate.
  // Near a seam with a stale calibration the two cameras may each put the
  // point in the other's part of the image: then it does not show at all.
  Eigen::Vector2d q = fusion.VehicleToPixel(p_vehicle);
  bool consistent = false;
  for (int iteration = 0; iteration < 4 && !consistent; ++iteration) {
    const auto [u, v] = round(q);
    const int c = fusion.PrimaryCamera(u, v);
    if (c < 0) return std::nullopt;
    const auto next = through(c);
    if (!next) return std::nullopt;
    q = *next;
    const auto [u2, v2] = round(q);
    consistent = fusion.PrimaryCamera(u2, v2) == c;
  }
  if (!consistent) return std::nullopt;
  // In a seam the fused value is a blend of two cameras: so is the point.
  const auto [u, v] = round(q);
  const int second = fusion.SecondaryCamera(u, v);
  const double w = fusion.PrimaryWeight(u, v);
  if (second >= 0 && w < 1.0) {
    const auto q2 = through(second);
    if (q2) q = w * q + (1.0 - w) * *q2;
  }
  return q;
}

}  // namespace parkslam::scene
