#include "parkslam/render/renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "parkslam/common/angles.h"
#include "parkslam/common/random.h"
#include "parkslam/common/seed_mix.h"
#include "parkslam/render/light_field.h"
#include "parkslam/render/sensor_noise.h"
#include "parkslam/scene/tag_texture.h"

namespace parkslam::render {
namespace {

using scene::kTagBlackCells;
using scene::kTagTotalCells;
using scene::Tag36h11Count;
using scene::Tag36h11Image;

constexpr std::uint64_t kCarStreamTag = 0xca7;
constexpr std::uint64_t kPedestrianStreamTag = 0x9ed;
constexpr std::uint64_t kNoiseStreamTag = 0x4015e;

// The lit floor is kept as a pyramid (2 cm, 4 cm, ... 64 cm per pixel) at
// half its radiance, so that light pools and daylight above 255 survive
// until the camera's gain and the final clamp.
constexpr int kGroundLevels = 6;
constexpr float kGroundRadianceScale = 2.0f;

// Azimuths in 1/65536 turn; obstacles are binned by azimuth in 2048 bins
// (0.18 degrees) around each camera per frame.
constexpr int kBinBits = 11;
constexpr int kBins = 1 << kBinBits;
constexpr int kBinShift = 16 - kBinBits;
constexpr double kTurnUnits = 65536.0;

constexpr int kTagPixelsPerCell = 16;
constexpr int kTagLevels = 5;  // 16, 8, 4, 2, 1 pixels per cell

constexpr double kMaxWallPieceM = 4.0;
constexpr double kHazeStart = 0.7;  // share of max_range_m where haze begins
constexpr double kEgoBodyBottomM = 0.25;

// Albedos: grey levels under unit light.
constexpr float kWallAlbedo = 175.0f;
constexpr float kPillarAlbedo = 185.0f;
constexpr float kSkirtingAlbedo = 80.0f;
constexpr float kStripeDarkAlbedo = 45.0f, kStripeLightAlbedo = 205.0f;
constexpr double kSkirtingHeightM = 0.12, kStripeHeightM = 0.8, kStripeWidthM = 0.2;
constexpr float kCeilingAlbedo = 55.0f;
constexpr float kHazeAlbedo = 40.0f;
constexpr float kLampRadiance = 600.0f;
constexpr float kTagBlack = 25.0f, kTagWhite = 235.0f;
constexpr float kEgoAlbedo = 110.0f;
constexpr float kTyreAlbedo = 25.0f, kGlassFactor = 0.3f;
constexpr float kHeadAlbedo = 150.0f;
constexpr float kDaylightAlbedo = 220.0f;  // the bright doorway of an opening

enum PixelKind : std::uint8_t { kInvalid, kGround, kCeiling, kFar, kEgo };

// Per pixel, read every frame.
struct HotRay {
  float x_m = 0, y_m = 0;     // ground or ceiling hit in the vehicle frame; ego: its radiance
  float env_s_m = 0;          // horizontal distance to that hit (max range when none)
  float gain = 0;             // brightness x vignetting
  std::uint16_t azimuth = 0;  // of the ray in the vehicle frame, 1/65536 turn
  std::uint8_t kind = kInvalid;
  std::uint8_t lod = 0;   // ground pyramid level
  std::uint8_t haze = 0;  // weight of haze at env_s_m, 0..255
};

// Per pixel, read only where an obstacle may be in the way.
struct ColdRay {
  float dx = 1, dy = 0;  // unit horizontal direction in the vehicle frame
  float slope = 0;       // rise per horizontal metre
  float pixel_angle_rad = 0;
};

struct CameraLut {
  std::string name;
  int width = 0, height = 0;
  Eigen::Vector3d c_vehicle = Eigen::Vector3d::Zero();
  std::vector<HotRay> hot;
  std::vector<ColdRay> cold;
};

enum class Surface : std::uint8_t { kWall, kPillar, kDaylight };

// A vertical rectangle from the floor to the ceiling above segment a-b.
struct Face {
  Eigen::Vector2d a_map, b_map;
  Eigen::Vector2d normal_map;  // the side a tag on it faces
  Surface surface = Surface::kWall;
  int tag = -1;  // index into Impl::tags
};

struct TagPatch {
  Eigen::Vector2d center_map;
  Eigen::Vector2d right_map;  // the viewer's right, facing the tag
  double z_center_m = 0.0;
  double cell_m = 0.0;
  std::array<cv::Mat, kTagLevels> texture;  // 16, 8, ... 1 pixels per cell
};

struct CarBody {
  Eigen::Vector2d center_map, axis_map;
  double half_length_m, half_width_m, height_m;
  float albedo;
};

struct Person {
  Eigen::Vector2d center_map;
  double radius_m, height_m;
  float albedo;
};

enum class Shape : std::uint8_t { kFace, kCar, kPerson };

// An obstacle near the camera this frame, in coordinates relative to the
// camera centre C (single precision is plenty there).
struct Candidate {
  float min_dist_m = 0;
  Shape shape = Shape::kFace;
  std::int32_t index = 0;
  float ox = 0, oy = 0;  // face: a - C; car: C - centre in the car frame; person: C - centre
  float ex = 0, ey = 0;  // face: b - a; car: unit length axis
  float k0 = 0, k1 = 0;  // car: half length, half width; person: |C - centre|^2 - r^2
  float top_m = 0;       // car and person heights
  int bin_first = 0, bin_count = 0;
};

// What every pixel of one frame of one camera shares.
struct Frame {
  Eigen::Vector2d c_map;  // camera centre
  float cz_m = 0;         // camera height
  float cos_yaw = 1, sin_yaw = 0;
  float light_at_camera = 1;
  float haze_radiance = 0;
};

struct Hit {
  float s_m;  // horizontal distance
  int candidate = -1;
  float u = 0;   // face: fraction along a-b
  int side = 0;  // car: 0 front/back, 1 sides, 2 roof
};

std::uint16_t ToTurnUnits(double angle_rad) {
  const double turns = angle_rad / (2.0 * kPi);
  const double units = (turns - std::floor(turns)) * kTurnUnits;
  return static_cast<std::uint16_t>(static_cast<std::uint32_t>(std::lround(units)) & 0xFFFFu);
}

// A random permutation of 0..n-1 (Fisher-Yates on parkslam::Random).
std::vector<int> Shuffled(int n, Random& rng) {
  std::vector<int> order(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) order[static_cast<size_t>(i)] = i;
  for (int i = n - 1; i > 0; --i) {
    const int j = static_cast<int>(rng.Index(static_cast<std::uint64_t>(i) + 1));
    std::swap(order[static_cast<size_t>(i)], order[static_cast<size_t>(j)]);
  }
  return order;
}

std::vector<ParkedCar> PlaceCars(const sim::World& world, int count, std::uint64_t seed) {
  Random rng = Random::Derive(seed, kCarStreamTag);
  const std::vector<int> order = Shuffled(static_cast<int>(world.slots.size()), rng);
  std::vector<ParkedCar> cars;
  for (int k = 0; k < count && k < static_cast<int>(order.size()); ++k) {
    const sim::WorldSlot& slot = world.slots[static_cast<size_t>(order[static_cast<size_t>(k)])];
    const auto& c = slot.corners_map;
    const Eigen::Vector2d entrance_mid = (c[0] + c[1]) / 2, back_mid = (c[2] + c[3]) / 2;
    const Eigen::Vector2d along_entrance = c[1] - c[0];
    const Eigen::Vector2d inward = back_mid - entrance_mid;
    const bool parallel = slot.kind == SlotKind::kParallel;
    const Eigen::Vector2d axis = (parallel ? along_entrance : inward).normalized();
    const Eigen::Vector2d other = parallel ? inward : along_entrance;
    const double room_along = parallel ? along_entrance.norm() : inward.norm();
    const double room_across = std::abs(axis.x() * other.y() - axis.y() * other.x());
    ParkedCar car;
    car.slot_index = order[static_cast<size_t>(k)];
    car.center_map = (entrance_mid + back_mid) / 2;
    car.yaw_rad = std::atan2(axis.y(), axis.x());
    car.length_m = std::min(rng.Uniform(4.2, 4.9), room_along - 0.5);
    car.width_m = std::min(rng.Uniform(1.7, 1.9), room_across - 0.4);
    car.height_m = rng.Uniform(1.4, 1.65);
    cars.push_back(car);
  }
  return cars;
}

std::vector<Pedestrian> PlacePedestrians(const sim::World& world, int count, std::uint64_t seed) {
  Random rng = Random::Derive(seed, kPedestrianStreamTag);
  std::vector<Pedestrian> people;
  for (int k = 0; k < count && !world.slots.empty(); ++k) {
    const sim::WorldSlot& slot = world.slots[rng.Index(world.slots.size())];
    const auto& c = slot.corners_map;
    const Eigen::Vector2d e = (c[1] - c[0]).normalized();
    const Eigen::Vector2d inward(-e.y(), e.x());
    Pedestrian p;
    p.center_map = (c[0] + c[1]) / 2 - inward * rng.Uniform(0.8, 2.5) + e * rng.Uniform(-1.0, 1.0);
    p.height_m = rng.Uniform(1.6, 1.85);
    people.push_back(p);
  }
  return people;
}

double SegmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                       const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double u = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + u * ab - p).norm();
}

struct FloorMap;  // defined beside the floor sampling

}  // namespace

struct Renderer::Impl {
  RenderOptions options;
  std::uint64_t seed = 0;
  GroundRaster ground;
  std::array<cv::Mat, kGroundLevels> lit_floor;
  LightField light;
  std::vector<Face> faces;
  std::vector<TagPatch> tags;
  std::vector<ParkedCar> cars;
  std::vector<CarBody> car_bodies;
  std::vector<Pedestrian> pedestrians;
  std::vector<Person> persons;
  std::vector<CameraLut> cameras;
  SensorNoise noise;

  Impl(const sim::World& world, const camera::CameraRig& rig, const RenderOptions& o,
       std::uint64_t s);

  void BakeFloor();
  void BuildObstacles(const sim::World& world);
  // The tags' textures; for each world tag, its patch.
  std::vector<int> BuildTagPatches(const sim::World& world);
  void AddWallFaces(const sim::World& world, const std::vector<int>& tag_of_world_tag);
  void AddPillarFaces(const sim::World& world, const std::vector<int>& tag_of_world_tag);
  CameraLut BuildLut(const camera::CameraConfig& config) const;
  double EnvironmentHit(const Eigen::Vector3d& d, double slope, double cz, double pixel_angle,
                        HotRay* hot) const;
  cv::Mat RenderCamera(const CameraLut& lut, size_t camera_index, const SE2& T_map_vehicle,
                       TimeNs t_ns) const;
  FloorMap FloorMapAt(const SE2& T_map_vehicle) const;
  // Radiance of an obstacle hit by the ray (dx, dy, slope) from the camera.
  float ShadeHit(const Frame& frame, const Candidate& candidate, const Hit& hit, float dx, float dy,
                 float slope, float pixel_angle_rad) const;
  // Albedo of the tag (with its white margin) at a face point; false off it.
  bool TagAlbedo(const TagPatch& tag, const Eigen::Vector2d& p_map, double z_m, double footprint_m,
                 float* albedo) const;
};

namespace {

GroundRasterOptions GroundOptionsOf(const RenderOptions& options) {
  GroundRasterOptions ground = options.ground;
  ground.stains = options.stains;
  return ground;
}

LightFieldOptions LightOptionsOf(const RenderOptions& options) {
  LightFieldOptions light;
  light.lamp_spacing_m = options.lamp_spacing_m;
  light.lamp_height_m = options.wall_height_m - 0.1;
  light.uneven_light = options.uneven_light;
  light.overexposure_near_entrance = options.overexposure_near_entrance;
  return light;
}

void ValidateOrThrow(const RenderOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument("RenderOptions: " + error);
}

}  // namespace

Renderer::Impl::Impl(const sim::World& world, const camera::CameraRig& rig, const RenderOptions& o,
                     std::uint64_t s)
    : options((ValidateOrThrow(o), o)),
      seed(s),
      ground(world, GroundOptionsOf(o), s),
      light(world, ground.min_x_m(), ground.max_y_m(), ground.image().cols * ground.resolution_m(),
            ground.image().rows * ground.resolution_m(), LightOptionsOf(o)),
      noise(o.noise_sigma) {
  BakeFloor();
  cars = PlaceCars(world, options.parked_cars, seed);
  pedestrians = PlacePedestrians(world, options.pedestrians, seed);
  BuildObstacles(world);
  for (const camera::CameraConfig& config : rig.cameras) cameras.push_back(BuildLut(config));
}

// The floor under the lamps, at half radiance, and its pyramid.
void Renderer::Impl::BakeFloor() {
  const cv::Mat& raster = ground.image();
  const double res = ground.resolution_m();
  cv::Mat lit(raster.size(), CV_8U);
  // The light changes over metres: evaluate it every 8 pixels along a row
  // and interpolate linearly between.
  constexpr int kStep = 8;
  std::vector<float> knots(static_cast<size_t>(raster.cols / kStep + 2));
  for (int r = 0; r < raster.rows; ++r) {
    const double y = ground.max_y_m() - (r + 0.5) * res;
    for (size_t k = 0; k < knots.size(); ++k) {
      knots[k] = light.At(ground.min_x_m() + (static_cast<double>(k) * kStep + 0.5) * res, y);
    }
    const std::uint8_t* src = raster.ptr<std::uint8_t>(r);
    std::uint8_t* dst = lit.ptr<std::uint8_t>(r);
    for (int c = 0; c < raster.cols; ++c) {
      const int k = c / kStep;
      const float w = static_cast<float>(c - k * kStep) / kStep;
      const float l = knots[static_cast<size_t>(k)] +
                      (knots[static_cast<size_t>(k) + 1] - knots[static_cast<size_t>(k)]) * w;
      dst[c] = cv::saturate_cast<std::uint8_t>(src[c] * l / kGroundRadianceScale);
    }
  }
  lit_floor[0] = lit;
  for (int l = 1; l < kGroundLevels; ++l) cv::pyrDown(lit_floor[l - 1], lit_floor[l]);
}

std::vector<int> Renderer::Impl::BuildTagPatches(const sim::World& world) {
  std::vector<int> tag_of_world_tag(world.tags.size(), -1);
  for (size_t i = 0; i < world.tags.size(); ++i) {
    const sim::WorldTag& t = world.tags[i];
    if (t.tag_id < 0 || t.tag_id >= Tag36h11Count()) {
      throw std::invalid_argument("tag " + std::to_string(t.tag_id) + " is not in tag36h11");
    }
    TagPatch patch;
    patch.center_map = t.p_map;
    const Eigen::Vector2d n(std::cos(t.normal_yaw_rad), std::sin(t.normal_yaw_rad));
    patch.right_map = Eigen::Vector2d(-n.y(), n.x());
    patch.z_center_m = options.tag_center_height_m;
    patch.cell_m = t.size_m / kTagBlackCells;
    patch.texture[0] = Tag36h11Image(t.tag_id, kTagPixelsPerCell);
    for (int l = 1; l < kTagLevels; ++l) {
      cv::resize(patch.texture[l - 1], patch.texture[l], cv::Size(), 0.5, 0.5, cv::INTER_AREA);
    }
    tag_of_world_tag[i] = static_cast<int>(tags.size());
    tags.push_back(std::move(patch));
  }
  return tag_of_world_tag;
}

// Walls: cut into pieces of at most kMaxWallPieceM, each holding at most
// one tag, so that the azimuth bins stay short.
void Renderer::Impl::AddWallFaces(const sim::World& world,
                                  const std::vector<int>& tag_of_world_tag) {
  const auto tag_half_extent_m = [&](const sim::WorldTag& t) {
    return (kTagTotalCells / 2.0 + options.tag_margin_cells) * t.size_m / kTagBlackCells + 0.05;
  };
  for (size_t w = 0; w < world.walls.size(); ++w) {
    const sim::WorldWall& wall = world.walls[w];
    const double length_m = (wall.b_map - wall.a_map).norm();
    if (length_m <= 0.0) continue;
    const Eigen::Vector2d dir = (wall.b_map - wall.a_map) / length_m;
    std::vector<double> cuts = {0.0, length_m};
    std::vector<std::pair<double, int>> wall_tags;
    for (size_t i = 0; i < world.tags.size(); ++i) {
      const sim::WorldTag& t = world.tags[i];
      if (t.on_pillar || t.mount_index != static_cast<int>(w)) continue;
      const double s = (t.p_map - wall.a_map).dot(dir);
      const double half = tag_half_extent_m(t);
      cuts.push_back(std::clamp(s - half, 0.0, length_m));
      cuts.push_back(std::clamp(s + half, 0.0, length_m));
      wall_tags.emplace_back(s, tag_of_world_tag[i]);
    }
    std::sort(cuts.begin(), cuts.end());
    for (size_t k = 0; k + 1 < cuts.size(); ++k) {
      const double s0 = cuts[k], s1 = cuts[k + 1];
      if (s1 - s0 < 1e-6) continue;
      int tag = -1;
      for (const auto& [s, index] : wall_tags) {
        if (s > s0 && s < s1) tag = index;
      }
      const int pieces = std::max(1, static_cast<int>(std::ceil((s1 - s0) / kMaxWallPieceM)));
      for (int p = 0; p < pieces; ++p) {
        const double p0 = s0 + (s1 - s0) * p / pieces, p1 = s0 + (s1 - s0) * (p + 1) / pieces;
        faces.push_back({wall.a_map + p0 * dir, wall.a_map + p1 * dir, wall.normal_map,
                         Surface::kWall, pieces == 1 ? tag : -1});
      }
    }
  }
}

void Renderer::Impl::AddPillarFaces(const sim::World& world,
                                    const std::vector<int>& tag_of_world_tag) {
  for (size_t p = 0; p < world.pillars.size(); ++p) {
    const sim::WorldPillar& pillar = world.pillars[p];
    for (int side = 0; side < 4; ++side) {
      const double yaw = side * kPi / 2;
      const Eigen::Vector2d n(std::cos(yaw), std::sin(yaw));
      const Eigen::Vector2d t(-n.y(), n.x());
      const Eigen::Vector2d mid = pillar.center_map + pillar.half_size_m * n;
      Face face{mid - pillar.half_size_m * t, mid + pillar.half_size_m * t, n, Surface::kPillar,
                -1};
      for (size_t i = 0; i < world.tags.size(); ++i) {
        const sim::WorldTag& tag = world.tags[i];
        if (tag.on_pillar && tag.mount_index == static_cast<int>(p) &&
            std::abs(AngleDiff(tag.normal_yaw_rad, yaw)) < 0.1) {
          face.tag = tag_of_world_tag[i];
        }
      }
      faces.push_back(face);
    }
  }
}

void Renderer::Impl::BuildObstacles(const sim::World& world) {
  // Tags first: faces refer to them.
  const std::vector<int> tag_of_world_tag = BuildTagPatches(world);
  AddWallFaces(world, tag_of_world_tag);
  AddPillarFaces(world, tag_of_world_tag);
  // Openings in the walls show daylight (under the entrance glow).
  for (const auto& [a, b] : WallOpenings(world)) {
    const Eigen::Vector2d d = (b - a).normalized();
    faces.push_back({a, b, Eigen::Vector2d(-d.y(), d.x()), Surface::kDaylight, -1});
  }
  Random rng = Random::Derive(seed, kCarStreamTag + 1);
  for (const ParkedCar& car : cars) {
    car_bodies.push_back({car.center_map,
                          {std::cos(car.yaw_rad), std::sin(car.yaw_rad)},
                          car.length_m / 2,
                          car.width_m / 2,
                          car.height_m,
                          static_cast<float>(rng.Uniform(30.0, 210.0))});
  }
  for (const Pedestrian& p : pedestrians) {
    persons.push_back(
        {p.center_map, p.radius_m, p.height_m, static_cast<float>(rng.Uniform(30.0, 120.0))});
  }
}

namespace {

// A camera's unit rays (vehicle frame) and their angles off its axis.
struct LutRays {
  std::vector<Eigen::Vector3d> rays;
  std::vector<double> off_axis_rad;
  std::vector<bool> valid;
  double max_off_axis_rad = 1e-9;
};

LutRays UnprojectRays(const camera::CameraModel& model, const Eigen::Matrix3d& R_vehicle_camera,
                      int width, int height) {
  const size_t n = static_cast<size_t>(width) * static_cast<size_t>(height);
  LutRays r;
  r.rays.assign(n, Eigen::Vector3d::Zero());
  r.off_axis_rad.assign(n, 0.0);
  r.valid.assign(n, false);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const size_t i = static_cast<size_t>(v) * static_cast<size_t>(width) + static_cast<size_t>(u);
      const std::optional<Eigen::Vector3d> ray = model.Unproject(Eigen::Vector2d(u, v));
      if (!ray) continue;
      r.valid[i] = true;
      r.rays[i] = R_vehicle_camera * ray->normalized();
      r.off_axis_rad[i] = std::acos(std::clamp(ray->normalized().z(), -1.0, 1.0));
      r.max_off_axis_rad = std::max(r.max_off_axis_rad, r.off_axis_rad[i]);
    }
  }
  return r;
}

// Angular size of pixel (u, v): geometric mean over both image axes of the
// angle to its neighbours; 1 / fx where it has none.
double PixelAngle(const LutRays& r, int width, int height, int u, int v, double fx) {
  const size_t i = static_cast<size_t>(v) * static_cast<size_t>(width) + static_cast<size_t>(u);
  const auto angle_to = [&](int du, int dv) -> double {
    const int u2 = u + du, v2 = v + dv;
    if (u2 < 0 || v2 < 0 || u2 >= width || v2 >= height) return -1.0;
    const size_t j = static_cast<size_t>(v2) * static_cast<size_t>(width) + static_cast<size_t>(u2);
    if (!r.valid[j]) return -1.0;
    return (r.rays[i] - r.rays[j]).norm();  // the chord: the angle, for neighbours
  };
  double ax = angle_to(1, 0), ay = angle_to(0, 1);
  if (ax < 0) ax = angle_to(-1, 0);
  if (ay < 0) ay = angle_to(0, -1);
  if (ax < 0) ax = ay;
  if (ay < 0) ay = ax;
  return ax > 0 ? std::sqrt(ax * ay) : 1.0 / fx;
}

// Slab test of the ray d from c against the vehicle's own body (box lo..hi):
// the axis of the face it enters through when it enters before the
// horizontal distance env_s; -1 otherwise. A camera on the body's surface
// sees the body behind it, not along it.
int EgoBodyEntryAxis(const Eigen::Vector3d& c, const Eigen::Vector3d& d, const Eigen::Vector3d& lo,
                     const Eigen::Vector3d& hi, double horizontal, double env_s) {
  double t_in = -1e30, t_out = 1e30;
  int entry_axis = -1;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-12) {
      if (c[k] < lo[k] || c[k] > hi[k]) t_out = -1.0;
      continue;
    }
    double t0 = (lo[k] - c[k]) / d[k];
    double t1 = (hi[k] - c[k]) / d[k];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > t_in) {
      t_in = t0;
      entry_axis = k;
    }
    t_out = std::min(t_out, t1);
  }
  if (entry_axis >= 0 && t_in >= -1e-9 && t_in < t_out && t_in * horizontal < env_s) {
    return entry_axis;
  }
  return -1;
}

}  // namespace

// Where the ray d (slope: rise per horizontal metre) meets the floor or the
// ceiling within range: sets hot's kind (kFar beyond) and floor level;
// returns the horizontal distance (the range when beyond).
double Renderer::Impl::EnvironmentHit(const Eigen::Vector3d& d, double slope, double cz,
                                      double pixel_angle, HotRay* hot) const {
  const double top = options.wall_height_m;
  const double range = options.max_range_m;
  const double res = ground.resolution_m();
  double env_s = range;
  hot->kind = kFar;
  if (slope < 0 && cz / -slope <= range) {
    env_s = cz / -slope;
    hot->kind = kGround;
    // The floor's footprint of the pixel: geometric mean of its extent
    // across (t * angle) and along (t * angle / sin(grazing)) the ray.
    const double t3d = cz / -d.z();
    const double footprint_m = t3d * pixel_angle / std::sqrt(-d.z());
    const double level = std::round(std::log2(std::max(footprint_m / res, 1.0)));
    hot->lod = static_cast<std::uint8_t>(std::min<double>(level, kGroundLevels - 1));
  } else if (slope > 0 && (top - cz) / slope <= range) {
    env_s = (top - cz) / slope;
    hot->kind = kCeiling;
  }
  return env_s;
}

CameraLut Renderer::Impl::BuildLut(const camera::CameraConfig& config) const {
  const camera::CameraModel model(config.intrinsics);
  CameraLut lut;
  lut.name = config.name;
  lut.width = model.width();
  lut.height = model.height();
  lut.c_vehicle = config.T_vehicle_camera.translation();
  const Eigen::Matrix3d R_vehicle_camera = config.T_vehicle_camera.linear();
  const size_t n = static_cast<size_t>(lut.width) * static_cast<size_t>(lut.height);
  const LutRays rays = UnprojectRays(model, R_vehicle_camera, lut.width, lut.height);
  const double cz = lut.c_vehicle.z();
  const double range = options.max_range_m;
  const VehicleParameters& car = options.vehicle;
  const Eigen::Vector3d ego_lo(-car.rear_overhang_m, -car.width_m / 2, kEgoBodyBottomM);
  const Eigen::Vector3d ego_hi(car.length_m - car.rear_overhang_m, car.width_m / 2,
                               options.ego_body_height_m);
  const bool camera_in_body = (lut.c_vehicle.array() > ego_lo.array()).all() &&
                              (lut.c_vehicle.array() < ego_hi.array()).all();
  const bool draw_body = options.ego_body && !camera_in_body;

  lut.hot.resize(n);
  lut.cold.resize(n);
  for (int v = 0; v < lut.height; ++v) {
    for (int u = 0; u < lut.width; ++u) {
      const size_t i =
          static_cast<size_t>(v) * static_cast<size_t>(lut.width) + static_cast<size_t>(u);
      HotRay& hot = lut.hot[i];
      ColdRay& cold = lut.cold[i];
      if (!rays.valid[i]) continue;
      const Eigen::Vector3d& d = rays.rays[i];
      const double pixel_angle =
          PixelAngle(rays, lut.width, lut.height, u, v, config.intrinsics.fx);

      // A ray straight up or down gets an arbitrary horizontal direction.
      const double horizontal = std::max(std::hypot(d.x(), d.y()), 1e-9);
      const bool vertical = horizontal <= 1e-9;
      cold.dx = static_cast<float>(vertical ? 1.0 : d.x() / horizontal);
      cold.dy = static_cast<float>(vertical ? 0.0 : d.y() / horizontal);
      const double slope = d.z() / horizontal;
      cold.slope = static_cast<float>(slope);
      cold.pixel_angle_rad = static_cast<float>(pixel_angle);
      hot.azimuth = ToTurnUnits(std::atan2(d.y(), d.x()));
      const double vignette = rays.off_axis_rad[i] / rays.max_off_axis_rad;
      hot.gain =
          static_cast<float>(options.brightness * (1.0 - options.vignetting * vignette * vignette));

      const double env_s = EnvironmentHit(d, slope, cz, pixel_angle, &hot);
      hot.x_m = static_cast<float>(lut.c_vehicle.x() + env_s * cold.dx);
      hot.y_m = static_cast<float>(lut.c_vehicle.y() + env_s * cold.dy);
      hot.env_s_m = static_cast<float>(env_s);
      const double haze =
          std::clamp((env_s - kHazeStart * range) / ((1 - kHazeStart) * range), 0.0, 1.0);
      hot.haze = static_cast<std::uint8_t>(std::lround(255 * haze));

      if (draw_body) {
        const int entry_axis =
            EgoBodyEntryAxis(lut.c_vehicle, d, ego_lo, ego_hi, horizontal, env_s);
        if (entry_axis >= 0) {
          hot.kind = kEgo;
          const double facing = 0.6 + 0.4 * std::abs(d[entry_axis]);
          hot.x_m = static_cast<float>(kEgoAlbedo * facing);
        }
      }
    }
  }
  return lut;
}

namespace {

// Per frame and camera: the obstacles within range, binned by azimuth
// around the camera centre, nearest first within every bin.
struct ObstacleBins {
  std::vector<Candidate> candidates;  // sorted by min_dist_m
  std::vector<int> start;             // kBins + 1 offsets into items
  std::vector<std::int32_t> items;    // candidate indices
  std::vector<float> nearest_m;       // per bin: min_dist_m of its first candidate
};

// Bins from azimuth lo_rad to hi_rad (hi_rad >= lo_rad), padded by one bin
// on either side for the rounding of pixel azimuths.
void SetBins(double lo_rad, double hi_rad, Candidate* c) {
  const double bins_per_rad = kBins / (2 * kPi);
  const int first = static_cast<int>(std::floor(lo_rad * bins_per_rad)) - 1;
  const int last = static_cast<int>(std::floor(hi_rad * bins_per_rad)) + 1;
  c->bin_first = ((first % kBins) + kBins) % kBins;
  c->bin_count = std::min(last - first + 1, kBins);
}

void SetAllBins(Candidate* c) {
  c->bin_first = 0;
  c->bin_count = kBins;
}

// The azimuth interval of points seen from c_map, all within half a turn of
// the azimuth of `center`.
void SetBinsAround(const Eigen::Vector2d& c_map, const Eigen::Vector2d& center,
                   const std::array<Eigen::Vector2d, 4>& points, Candidate* c) {
  const double mid = std::atan2(center.y() - c_map.y(), center.x() - c_map.x());
  double lo = 0.0, hi = 0.0;
  for (const Eigen::Vector2d& p : points) {
    const double rel = AngleDiff(std::atan2(p.y() - c_map.y(), p.x() - c_map.x()), mid);
    lo = std::min(lo, rel);
    hi = std::max(hi, rel);
  }
  SetBins(mid + lo, mid + hi, c);
}

// The faces within range_m of C, with their azimuth bins.
void AddFaceCandidates(const std::vector<Face>& faces, const Eigen::Vector2d& C, double range_m,
                       std::vector<Candidate>* candidates) {
  std::vector<Candidate>& cands = *candidates;
  for (size_t i = 0; i < faces.size(); ++i) {
    const Face& f = faces[i];
    const double dist = SegmentDistance(C, f.a_map, f.b_map);
    if (dist > range_m) continue;
    Candidate c;
    c.min_dist_m = static_cast<float>(dist);
    c.shape = Shape::kFace;
    c.index = static_cast<std::int32_t>(i);
    c.ox = static_cast<float>(f.a_map.x() - C.x());
    c.oy = static_cast<float>(f.a_map.y() - C.y());
    c.ex = static_cast<float>(f.b_map.x() - f.a_map.x());
    c.ey = static_cast<float>(f.b_map.y() - f.a_map.y());
    const double az_a = std::atan2(f.a_map.y() - C.y(), f.a_map.x() - C.x());
    const double az_b = std::atan2(f.b_map.y() - C.y(), f.b_map.x() - C.x());
    const double diff = AngleDiff(az_b, az_a);
    const double lo = diff >= 0 ? az_a : az_b;
    SetBins(lo, lo + std::abs(diff), &c);
    cands.push_back(c);
  }
}

// The parked cars within range_m of C, in their own frames.
void AddCarCandidates(const std::vector<CarBody>& cars, const Eigen::Vector2d& C, double range_m,
                      std::vector<Candidate>* candidates) {
  std::vector<Candidate>& cands = *candidates;
  for (size_t i = 0; i < cars.size(); ++i) {
    const CarBody& b = cars[i];
    const Eigen::Vector2d across(-b.axis_map.y(), b.axis_map.x());
    const Eigen::Vector2d local((C - b.center_map).dot(b.axis_map), (C - b.center_map).dot(across));
    const Eigen::Vector2d outside =
        (local.cwiseAbs() - Eigen::Vector2d(b.half_length_m, b.half_width_m)).cwiseMax(0.0);
    const double dist = outside.norm();
    if (dist > range_m) continue;
    Candidate c;
    c.min_dist_m = static_cast<float>(dist);
    c.shape = Shape::kCar;
    c.index = static_cast<std::int32_t>(i);
    c.ox = static_cast<float>(local.x());
    c.oy = static_cast<float>(local.y());
    c.ex = static_cast<float>(b.axis_map.x());
    c.ey = static_cast<float>(b.axis_map.y());
    c.k0 = static_cast<float>(b.half_length_m);
    c.k1 = static_cast<float>(b.half_width_m);
    c.top_m = static_cast<float>(b.height_m);
    if (dist <= 0.0) {
      SetAllBins(&c);
    } else {
      const Eigen::Vector2d l = b.half_length_m * b.axis_map, w = b.half_width_m * across;
      SetBinsAround(
          C, b.center_map,
          {b.center_map + l + w, b.center_map + l - w, b.center_map - l + w, b.center_map - l - w},
          &c);
    }
    cands.push_back(c);
  }
}

// The pedestrians within range_m of C.
void AddPersonCandidates(const std::vector<Person>& persons, const Eigen::Vector2d& C,
                         double range_m, std::vector<Candidate>* candidates) {
  std::vector<Candidate>& cands = *candidates;
  for (size_t i = 0; i < persons.size(); ++i) {
    const Person& p = persons[i];
    const Eigen::Vector2d o = C - p.center_map;
    const double centre_dist = o.norm();
    const double dist = std::max(centre_dist - p.radius_m, 0.0);
    if (dist > range_m) continue;
    Candidate c;
    c.min_dist_m = static_cast<float>(dist);
    c.shape = Shape::kPerson;
    c.index = static_cast<std::int32_t>(i);
    c.ox = static_cast<float>(o.x());
    c.oy = static_cast<float>(o.y());
    c.k0 = static_cast<float>(o.squaredNorm() - p.radius_m * p.radius_m);
    c.k1 = static_cast<float>(p.radius_m);
    c.top_m = static_cast<float>(p.height_m);
    if (centre_dist <= p.radius_m) {
      SetAllBins(&c);
    } else {
      const double mid = std::atan2(-o.y(), -o.x());
      const double half = std::asin(p.radius_m / centre_dist);
      SetBins(mid - half, mid + half, &c);
    }
    cands.push_back(c);
  }
}

// The candidates (sorted nearest first) into their bins.
void FillBins(ObstacleBins* obstacle_bins) {
  ObstacleBins& bins = *obstacle_bins;
  const std::vector<Candidate>& cands = bins.candidates;
  // Counting sort into the bins keeps every bin's list nearest first.
  bins.start.assign(kBins + 1, 0);
  for (const Candidate& c : cands) {
    for (int k = 0; k < c.bin_count; ++k) ++bins.start[((c.bin_first + k) & (kBins - 1)) + 1];
  }
  for (int b = 0; b < kBins; ++b) bins.start[b + 1] += bins.start[b];
  bins.items.resize(static_cast<size_t>(bins.start[kBins]));
  std::vector<int> cursor(bins.start.begin(), bins.start.end() - 1);
  for (size_t i = 0; i < cands.size(); ++i) {
    const Candidate& c = cands[i];
    for (int k = 0; k < c.bin_count; ++k) {
      const int b = (c.bin_first + k) & (kBins - 1);
      bins.items[static_cast<size_t>(cursor[b]++)] = static_cast<std::int32_t>(i);
    }
  }
  bins.nearest_m.assign(kBins, std::numeric_limits<float>::infinity());
  for (int b = 0; b < kBins; ++b) {
    if (bins.start[b] < bins.start[b + 1]) {
      bins.nearest_m[b] = cands[static_cast<size_t>(bins.items[bins.start[b]])].min_dist_m;
    }
  }
}

ObstacleBins BinObstacles(const std::vector<Face>& faces, const std::vector<CarBody>& cars,
                          const std::vector<Person>& persons, const Eigen::Vector2d& C,
                          double range_m) {
  ObstacleBins bins;
  std::vector<Candidate>& cands = bins.candidates;
  AddFaceCandidates(faces, C, range_m, &cands);
  AddCarCandidates(cars, C, range_m, &cands);
  AddPersonCandidates(persons, C, range_m, &cands);
  std::sort(cands.begin(), cands.end(), [](const Candidate& a, const Candidate& b) {
    if (a.min_dist_m != b.min_dist_m) return a.min_dist_m < b.min_dist_m;
    if (a.shape != b.shape) return a.shape < b.shape;
    return a.index < b.index;
  });
  FillBins(&bins);
  return bins;
}

// Ray-obstacle tests on the horizontal distance s along the ray
// (horizontal direction (dx, dy), height cz + s * slope). Each keeps the
// nearer hit.

// A face reaches from the floor to the ceiling, so a ray that meets its
// segment before the ray's own floor or ceiling hit meets the face.
inline void IntersectFace(const Candidate& c, float dx, float dy, int index, Hit* hit) {
  const float denom = dx * c.ey - dy * c.ex;
  if (std::abs(denom) < 1e-12f) return;
  const float inv = 1.0f / denom;
  const float s = (c.ox * c.ey - c.oy * c.ex) * inv;
  if (!(s > 1e-3f && s < hit->s_m)) return;
  const float u = (c.ox * dy - c.oy * dx) * inv;
  if (u < -1e-5f || u > 1.0f + 1e-5f) return;
  hit->s_m = s;
  hit->candidate = index;
  hit->u = u;
}

// Slab test of the box |l| <= k0, |w| <= k1, 0 <= z <= top_m in the car frame.
inline void IntersectCar(const Candidate& c, float dx, float dy, float slope, float cz, int index,
                         Hit* hit) {
  const float dl = dx * c.ex + dy * c.ey;
  const float dw = -dx * c.ey + dy * c.ex;
  float enter = -std::numeric_limits<float>::infinity();
  float leave = hit->s_m;
  int side = -1;
  const std::array<float, 3> origin = {c.ox, c.oy, cz - c.top_m / 2};
  const std::array<float, 3> dir = {dl, dw, slope};
  const std::array<float, 3> half = {c.k0, c.k1, c.top_m / 2};
  for (int k = 0; k < 3; ++k) {
    if (std::abs(dir[k]) < 1e-9f) {
      if (std::abs(origin[k]) > half[k]) return;
      continue;
    }
    float t0 = (-half[k] - origin[k]) / dir[k];
    float t1 = (half[k] - origin[k]) / dir[k];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > enter) {
      enter = t0;
      side = k;
    }
    leave = std::min(leave, t1);
  }
  if (side < 0 || !(enter > 1e-3f) || enter > leave || enter >= hit->s_m) return;
  hit->s_m = enter;
  hit->candidate = index;
  hit->side = side;
}

inline void IntersectPerson(const Candidate& c, float dx, float dy, float slope, float cz,
                            int index, Hit* hit) {
  const float b = c.ox * dx + c.oy * dy;
  const float disc = b * b - c.k0;
  if (disc < 0.0f) return;
  const float s = -b - std::sqrt(disc);
  if (!(s > 1e-3f && s < hit->s_m)) return;
  const float z = cz + s * slope;
  if (z < 0.0f || z > c.top_m) return;
  hit->s_m = s;
  hit->candidate = index;
}

// One level of the lit floor pyramid, for bilinear sampling.
struct FloorLevel {
  const std::uint8_t* data = nullptr;
  size_t step = 0;
  float max_x = 0, max_y = 0;  // last valid top-left corner of a 2 x 2 neighbourhood
  float scale = 1;             // level-0 pixel coordinates to this level's
};

inline float SampleFloor(const FloorLevel& level, float x0, float y0) {
  const float x = std::clamp(x0 * level.scale, 0.0f, level.max_x);
  const float y = std::clamp(y0 * level.scale, 0.0f, level.max_y);
  const int ix = static_cast<int>(x), iy = static_cast<int>(y);
  const float wx = x - static_cast<float>(ix), wy = y - static_cast<float>(iy);
  const std::uint8_t* p = level.data + static_cast<size_t>(iy) * level.step + ix;
  const float top = p[0] + static_cast<float>(p[1] - p[0]) * wx;
  const float bottom = p[level.step] + static_cast<float>(p[level.step + 1] - p[level.step]) * wx;
  return top + (bottom - top) * wy;
}

// The nearest obstacle of the bin that the ray (dx, dy, slope) from a
// camera at height cz_m meets before env_s_m; hit.candidate < 0 when none.
inline Hit NearestObstacle(const ObstacleBins& bins, int bin, float env_s_m, float dx, float dy,
                           float slope, float cz_m) {
  Hit hit{env_s_m};
  for (int k = bins.start[bin]; k < bins.start[bin + 1]; ++k) {
    const int index = bins.items[static_cast<size_t>(k)];
    const Candidate& cand = bins.candidates[static_cast<size_t>(index)];
    if (cand.min_dist_m >= hit.s_m) break;
    switch (cand.shape) {
      case Shape::kFace:
        IntersectFace(cand, dx, dy, index, &hit);
        break;
      case Shape::kCar:
        IntersectCar(cand, dx, dy, slope, cz_m, index, &hit);
        break;
      case Shape::kPerson:
        IntersectPerson(cand, dx, dy, slope, cz_m, index, &hit);
        break;
    }
  }
  return hit;
}

// Level-0 floor pixel of a vehicle-frame point (x, y), affine per frame
// (x: fx0 + fx1 x + fx2 y), and the floor's levels.
struct FloorMap {
  float fx0 = 0, fx1 = 0, fx2 = 0, fy0 = 0, fy1 = 0, fy2 = 0;
  std::array<FloorLevel, kGroundLevels> levels;
};

inline float Bilinear(const cv::Mat& image, double x, double y) {
  const double cx = std::clamp(x, 0.0, image.cols - 1.001);
  const double cy = std::clamp(y, 0.0, image.rows - 1.001);
  const int ix = static_cast<int>(cx), iy = static_cast<int>(cy);
  const float wx = static_cast<float>(cx - ix), wy = static_cast<float>(cy - iy);
  const std::uint8_t* r0 = image.ptr<std::uint8_t>(iy) + ix;
  const std::uint8_t* r1 = image.ptr<std::uint8_t>(iy + 1) + ix;
  const float top = r0[0] + static_cast<float>(r0[1] - r0[0]) * wx;
  const float bottom = r1[0] + static_cast<float>(r1[1] - r1[0]) * wx;
  return top + (bottom - top) * wy;
}

}  // namespace

bool Renderer::Impl::TagAlbedo(const TagPatch& tag, const Eigen::Vector2d& p_map, double z_m,
                               double footprint_m, float* albedo) const {
  const double half = kTagTotalCells / 2.0;
  const double u = (p_map - tag.center_map).dot(tag.right_map) / tag.cell_m + half;
  const double v = (tag.z_center_m - z_m) / tag.cell_m + half;
  const double margin = options.tag_margin_cells;
  if (u < -margin || v < -margin || u > kTagTotalCells + margin || v > kTagTotalCells + margin) {
    return false;
  }
  float texel = 255.0f;
  if (u >= 0.0 && v >= 0.0 && u < kTagTotalCells && v < kTagTotalCells) {
    const double texel0_m = tag.cell_m / kTagPixelsPerCell;
    const int level = std::clamp(static_cast<int>(std::floor(std::log2(footprint_m / texel0_m))), 0,
                                 kTagLevels - 1);
    const double per_cell = static_cast<double>(kTagPixelsPerCell >> level);
    texel =
        Bilinear(tag.texture[static_cast<size_t>(level)], u * per_cell - 0.5, v * per_cell - 0.5);
  }
  *albedo = kTagBlack + (kTagWhite - kTagBlack) * texel / 255.0f;
  return true;
}

float Renderer::Impl::ShadeHit(const Frame& frame, const Candidate& candidate, const Hit& hit,
                               float dx, float dy, float slope, float pixel_angle_rad) const {
  const Eigen::Vector2d p_map = frame.c_map + Eigen::Vector2d(dx, dy) * hit.s_m;
  const float z = frame.cz_m + hit.s_m * slope;
  float albedo = 0.0f, facing = 1.0f;
  switch (candidate.shape) {
    case Shape::kFace: {
      const Face& face = faces[static_cast<size_t>(candidate.index)];
      const float cos_incidence =
          static_cast<float>(dx * face.normal_map.x() + dy * face.normal_map.y());
      facing = 0.6f + 0.4f * std::abs(cos_incidence);
      if (face.tag >= 0 && cos_incidence < 0.0f) {
        const double footprint_m = hit.s_m * std::sqrt(1.0 + slope * slope) * pixel_angle_rad /
                                   std::max(std::abs(cos_incidence), 0.2f);
        if (TagAlbedo(tags[static_cast<size_t>(face.tag)], p_map, z, footprint_m, &albedo)) break;
      }
      if (face.surface == Surface::kDaylight) {
        albedo = kDaylightAlbedo;
        facing = 1.0f;
      } else if (face.surface == Surface::kPillar && z < kStripeHeightM) {
        // Hazard stripes round the foot of the pillar.
        const double along_m = hit.u * std::hypot(candidate.ex, candidate.ey);
        const bool dark = static_cast<int>(std::floor((along_m + z) / kStripeWidthM)) % 2 == 0;
        albedo = dark ? kStripeDarkAlbedo : kStripeLightAlbedo;
      } else if (z < kSkirtingHeightM) {
        albedo = kSkirtingAlbedo;
      } else {
        albedo = face.surface == Surface::kPillar ? kPillarAlbedo : kWallAlbedo;
      }
      break;
    }
    case Shape::kCar: {
      const CarBody& car = car_bodies[static_cast<size_t>(candidate.index)];
      const float h = static_cast<float>(car.height_m);
      if (hit.side == 2) {
        albedo = car.albedo * 1.1f;
      } else {
        const float d_local = hit.side == 0 ? dx * candidate.ex + dy * candidate.ey
                                            : -dx * candidate.ey + dy * candidate.ex;
        facing = 0.6f + 0.4f * std::abs(d_local);
        albedo = z < 0.3f                           ? kTyreAlbedo
                 : (z > 0.62f * h && z < 0.92f * h) ? car.albedo * kGlassFactor
                                                    : car.albedo;
      }
      break;
    }
    case Shape::kPerson: {
      const Person& person = persons[static_cast<size_t>(candidate.index)];
      albedo = z > person.height_m - 0.25 ? kHeadAlbedo : person.albedo;
      facing = 0.8f;
      break;
    }
  }
  return albedo * facing * light.At(p_map.x(), p_map.y());
}

FloorMap Renderer::Impl::FloorMapAt(const SE2& T_map_vehicle) const {
  const double cos_yaw = std::cos(T_map_vehicle.yaw()), sin_yaw = std::sin(T_map_vehicle.yaw());
  const double inv_res = 1.0 / ground.resolution_m();
  FloorMap f;
  f.fx0 = static_cast<float>((T_map_vehicle.x() - ground.min_x_m()) * inv_res - 0.5);
  f.fx1 = static_cast<float>(cos_yaw * inv_res);
  f.fx2 = static_cast<float>(-sin_yaw * inv_res);
  f.fy0 = static_cast<float>((ground.max_y_m() - T_map_vehicle.y()) * inv_res - 0.5);
  f.fy1 = static_cast<float>(-sin_yaw * inv_res);
  f.fy2 = static_cast<float>(-cos_yaw * inv_res);
  for (int l = 0; l < kGroundLevels; ++l) {
    const cv::Mat& m = lit_floor[static_cast<size_t>(l)];
    f.levels[static_cast<size_t>(l)] = {m.data, m.step[0], m.cols - 1.001f, m.rows - 1.001f,
                                        1.0f / static_cast<float>(1 << l)};
  }
  return f;
}

cv::Mat Renderer::Impl::RenderCamera(const CameraLut& lut, size_t camera_index,
                                     const SE2& T_map_vehicle, TimeNs t_ns) const {
  cv::Mat image(lut.height, lut.width, CV_8UC1);
  Frame frame;
  const double cos_yaw = std::cos(T_map_vehicle.yaw()), sin_yaw = std::sin(T_map_vehicle.yaw());
  frame.c_map = T_map_vehicle * Eigen::Vector2d(lut.c_vehicle.head<2>());
  frame.cz_m = static_cast<float>(lut.c_vehicle.z());
  frame.cos_yaw = static_cast<float>(cos_yaw);
  frame.sin_yaw = static_cast<float>(sin_yaw);
  frame.light_at_camera = light.At(frame.c_map.x(), frame.c_map.y());
  frame.haze_radiance = kHazeAlbedo * frame.light_at_camera;
  const std::uint32_t yaw_units = ToTurnUnits(T_map_vehicle.yaw());
  const ObstacleBins bins =
      BinObstacles(faces, car_bodies, persons, frame.c_map, options.max_range_m);

  const FloorMap floor = FloorMapAt(T_map_vehicle);
  const float fx0 = floor.fx0, fx1 = floor.fx1, fx2 = floor.fx2;
  const float fy0 = floor.fy0, fy1 = floor.fy1, fy2 = floor.fy2;
  const std::array<FloorLevel, kGroundLevels>& levels = floor.levels;

  const float tx = static_cast<float>(T_map_vehicle.x());
  const float ty = static_cast<float>(T_map_vehicle.y());
  const float ceiling_radiance = kCeilingAlbedo * frame.light_at_camera;
  const size_t n = lut.hot.size();
  std::uint8_t* out = image.ptr<std::uint8_t>(0);
  for (size_t i = 0; i < n; ++i) {
    const HotRay& h = lut.hot[i];
    if (h.kind == kInvalid) {
      out[i] = 0;
      continue;
    }
    float radiance = 0.0f;
    if (h.kind == kEgo) {
      radiance = h.x_m * frame.light_at_camera;
    } else {
      bool hit_obstacle = false;
      const int bin = static_cast<int>(((h.azimuth + yaw_units) & 0xFFFFu) >> kBinShift);
      if (bins.nearest_m[static_cast<size_t>(bin)] < h.env_s_m) {
        const ColdRay& c = lut.cold[i];
        const float dx = c.dx * frame.cos_yaw - c.dy * frame.sin_yaw;
        const float dy = c.dx * frame.sin_yaw + c.dy * frame.cos_yaw;
        const Hit hit = NearestObstacle(bins, bin, h.env_s_m, dx, dy, c.slope, frame.cz_m);
        if (hit.candidate >= 0) {
          hit_obstacle = true;
          radiance = ShadeHit(frame, bins.candidates[static_cast<size_t>(hit.candidate)], hit, dx,
                              dy, c.slope, c.pixel_angle_rad);
          const float range = static_cast<float>(options.max_range_m);
          const float haze = std::clamp((hit.s_m - static_cast<float>(kHazeStart) * range) /
                                            (static_cast<float>(1 - kHazeStart) * range),
                                        0.0f, 1.0f);
          radiance += (frame.haze_radiance - radiance) * haze;
        }
      }
      if (!hit_obstacle) {
        if (h.kind == kGround) {
          radiance =
              kGroundRadianceScale * SampleFloor(levels[h.lod], fx0 + fx1 * h.x_m + fx2 * h.y_m,
                                                 fy0 + fy1 * h.x_m + fy2 * h.y_m);
        } else if (h.kind == kCeiling) {
          // The ceiling is lit by the floor's reflection: evenly, as at the camera.
          const float x = tx + frame.cos_yaw * h.x_m - frame.sin_yaw * h.y_m;
          const float y = ty + frame.sin_yaw * h.x_m + frame.cos_yaw * h.y_m;
          radiance = light.IsLamp(x, y) ? kLampRadiance : ceiling_radiance;
        } else {
          radiance = frame.haze_radiance;
        }
        radiance += (frame.haze_radiance - radiance) * (static_cast<float>(h.haze) * (1.0f / 255));
      }
    }
    const float value = std::clamp(radiance * h.gain, 0.0f, 255.0f);
    out[i] = static_cast<std::uint8_t>(value + 0.5f);
  }

  if (options.blur_sigma_px > 0.0) {
    cv::GaussianBlur(image, image, cv::Size(0, 0), options.blur_sigma_px);
  }
  noise.Apply(MixSeed(seed + static_cast<std::uint64_t>(t_ns), kNoiseStreamTag + camera_index),
              &image);
  return image;
}

bool RenderOptions::IsValid(std::string* error) const {
  const auto fail = [error](const std::string& what) {
    if (error != nullptr) *error = what;
    return false;
  };
  if (!(brightness >= 0.0 && brightness <= 10.0)) return fail("brightness must be in [0, 10]");
  if (!(uneven_light >= 0.0 && uneven_light <= 1.0)) return fail("uneven_light must be in [0, 1]");
  if (!(overexposure_near_entrance >= 0.0 && overexposure_near_entrance <= 5.0)) {
    return fail("overexposure_near_entrance must be in [0, 5]");
  }
  if (!(noise_sigma >= 0.0 && noise_sigma <= 100.0)) return fail("noise_sigma must be in [0, 100]");
  if (!(blur_sigma_px >= 0.0 && blur_sigma_px <= 20.0))
    return fail("blur_sigma_px must be in [0, 20]");
  if (!(vignetting >= 0.0 && vignetting <= 1.0)) return fail("vignetting must be in [0, 1]");
  if (parked_cars < 0 || pedestrians < 0) return fail("parked_cars and pedestrians must be >= 0");
  if (!(ego_body_height_m > kEgoBodyBottomM)) return fail("ego_body_height_m must exceed 0.25");
  if (!(wall_height_m > 0.5 && wall_height_m < 20.0))
    return fail("wall_height_m must be in (0.5, 20)");
  if (!(tag_center_height_m > 0.0 && tag_center_height_m < wall_height_m)) {
    return fail("tag_center_height_m must be in (0, wall_height_m)");
  }
  if (!(tag_margin_cells >= 0.0 && tag_margin_cells <= 10.0))
    return fail("tag_margin_cells must be in [0, 10]");
  if (!(lamp_spacing_m >= 1.0)) return fail("lamp_spacing_m must be at least 1");
  if (!(max_range_m > 1.0 && max_range_m <= 200.0)) return fail("max_range_m must be in (1, 200]");
  std::string vehicle_error;
  if (!vehicle.IsValid(&vehicle_error)) return fail("vehicle: " + vehicle_error);
  std::string ground_error;
  if (!ground.IsValid(&ground_error)) return fail("ground: " + ground_error);
  return true;
}

Eigen::Isometry3d VehiclePose3d(const SE2& T_map_vehicle) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(T_map_vehicle.yaw(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(T_map_vehicle.x(), T_map_vehicle.y(), 0.0);
  return T;
}

Eigen::Vector3d TagCenter3d(const sim::WorldTag& tag, const RenderOptions& options) {
  return {tag.p_map.x(), tag.p_map.y(), options.tag_center_height_m};
}

Renderer::Renderer(const sim::World& world, const camera::CameraRig& rig,
                   const RenderOptions& options, std::uint64_t seed)
    : impl_(std::make_unique<Impl>(world, rig, options, seed)) {}

Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

cv::Mat Renderer::Render(const std::string& camera_name, const SE2& T_map_vehicle,
                         TimeNs t_ns) const {
  for (size_t i = 0; i < impl_->cameras.size(); ++i) {
    if (impl_->cameras[i].name == camera_name) {
      return impl_->RenderCamera(impl_->cameras[i], i, T_map_vehicle, t_ns);
    }
  }
  throw std::invalid_argument("the rig has no camera \"" + camera_name + "\"");
}

std::vector<cv::Mat> Renderer::RenderAll(const SE2& T_map_vehicle, TimeNs t_ns,
                                         const std::vector<std::string>& camera_names) const {
  std::vector<cv::Mat> images;
  images.reserve(camera_names.size());
  for (const std::string& name : camera_names) images.push_back(Render(name, T_map_vehicle, t_ns));
  return images;
}

const GroundRaster& Renderer::ground() const { return impl_->ground; }
const RenderOptions& Renderer::options() const { return impl_->options; }
const std::vector<ParkedCar>& Renderer::parked_cars() const { return impl_->cars; }
const std::vector<Pedestrian>& Renderer::pedestrians() const { return impl_->pedestrians; }

}  // namespace parkslam::render
