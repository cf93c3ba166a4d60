#include "parkslam/scene/lot_scene.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <tuple>

#include "parkslam/common/angles.h"
#include "parkslam/common/random.h"
#include "parkslam/common/seed_mix.h"

namespace parkslam::scene {
namespace {

constexpr double kCeilingM = 3.0;  // walls and pillars reach the renderer's ceiling
constexpr double kWallThicknessM = 0.2;
constexpr double kTagCentreHeightM = 1.35;  // as the front camera's tag band expects
constexpr double kTagStandOffM = 0.005;     // in front of its face, so that the face never hides it

// Streams of the look's seed, one per part, so that changing one part's
// draws leaves the others as they were.
constexpr std::uint64_t kPaintTag = 0x1a7;
constexpr std::uint64_t kLookTag = 0x10c;
constexpr std::uint64_t kCarsTag = 0xca5;
constexpr std::uint64_t kDirtTag = 0xd17;
constexpr std::uint64_t kWallsTag = 0x3a11;

Eigen::Vector2d Heading(double yaw) { return {std::cos(yaw), std::sin(yaw)}; }

// The lot's extent: slots, walls and pillars, with a margin.
struct Extent {
  Eigen::Vector2d min = Eigen::Vector2d::Constant(1e18), max = Eigen::Vector2d::Constant(-1e18);
  void Add(const Eigen::Vector2d& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
};

// How one lot family paints its slots, drawn from the look.
struct LotPaint {
  PaintKind paint = PaintKind::kWhite;
  double line_width_m = 0.15;
  double opacity = 0.95, wear = 0.05;
  bool entrance_line = false;  // a continuous entrance line; else stubs at the corners
  double stub_m = 0.5;
  bool back_line = true;
  bool repainted = false;  // the ghost of an older layout beside today's lines
  // Where IDs are painted: 0 inside the slot behind the entrance, read
  // from the aisle; 1 the same, read from the slot; 2 along a separating
  // line (turned a quarter).
  int id_place = 0;
  double id_height_m = 0.5, id_setback_m = 0.3;
  int font = 0;  // into the font book
  bool bold = true;
  double stretch = 1.0;
};

// Each preset bends the sampled look and paint towards its kind of lot;
// "seed" keeps the draws.
void ApplyPreset(const std::string& preset, Random& rng, Look* look, LotPaint* paint) {
  Floor& f = look->floor;
  Lighting& l = look->light;
  if (preset == "seed") return;
  // A preset's cameras are a unit in good order: no dirt, no motion blur,
  // little compression; their own exposure, noise and white balance stay.
  for (CameraLook& c : look->cameras) {
    c.dirt_spots = 0;
    c.motion_blur_px = 0.0;
    c.jpeg_quality = std::max(c.jpeg_quality, 85);
    c.glare = 0.0;
  }
  paint->paint = PaintKind::kWhite;
  if (preset == "epoxy") {
    f.material = FloorMaterial::kEpoxy;
    f.base = Colour(150, 165, 150) * static_cast<float>(rng.Uniform(0.95, 1.1));
    f.gloss = rng.Uniform(0.4, 0.7);
    f.texture = rng.Uniform(0.2, 0.5);
    f.blotches = rng.Uniform(0.3, 0.7);
    l.gain = rng.Uniform(1.15, 1.4);
    l.pools = rng.Uniform(0.1, 0.3);
    l.night = false;
    l.backlight = 0.0;
    paint->opacity = rng.Uniform(0.9, 1.0);
    paint->wear = rng.Uniform(0.0, 0.08);
  } else if (preset == "concrete") {
    f.material = FloorMaterial::kConcrete;
    f.base = Colour(120, 122, 125) * static_cast<float>(rng.Uniform(0.85, 1.05));
    f.gloss = 0.0;
    f.texture = rng.Uniform(1.1, 1.5);
    f.blotches = rng.Uniform(1.2, 1.6);
    l.gain = rng.Uniform(0.5, 0.65);
    l.pools = rng.Uniform(0.4, 0.6);
    l.night = false;
    paint->opacity = rng.Uniform(0.6, 0.8);
    paint->wear = rng.Uniform(0.25, 0.4);
  } else if (preset == "underground") {
    f.material = FloorMaterial::kConcrete;
    f.base = Colour(105, 110, 112) * static_cast<float>(rng.Uniform(0.9, 1.1));
    f.gloss = rng.Uniform(0.5, 0.8);  // sealed and wet: the lamps mirror in it
    f.blotches = rng.Uniform(0.8, 1.4);
    l.gain = rng.Uniform(0.7, 0.9);
    l.pools = rng.Uniform(0.5, 0.7);
    l.lamp_spacing_m = rng.Uniform(5.0, 7.0);
    l.night = false;
    for (CameraLook& c : look->cameras) c.glare = rng.Bernoulli(0.5) ? rng.Uniform(0.2, 0.4) : 0.0;
    paint->opacity = rng.Uniform(0.75, 0.9);
    paint->wear = rng.Uniform(0.1, 0.25);
  } else if (preset == "outdoor") {
    f.material = FloorMaterial::kAsphalt;
    f.base = Colour(70, 72, 75) * static_cast<float>(rng.Uniform(0.85, 1.15));
    f.verge = false;
    l.sun_elevation_rad = rng.Uniform(0.5, 0.9);
    l.shadow_depth = rng.Uniform(0.55, 0.7);
    l.trees = 0;
    paint->opacity = rng.Uniform(0.85, 1.0);
    paint->wear = rng.Uniform(0.05, 0.2);
  } else if (preset == "yellow") {
    f.material = FloorMaterial::kConcrete;
    f.base = Colour(135, 138, 140) * static_cast<float>(rng.Uniform(0.9, 1.1));
    l.gain = rng.Uniform(0.8, 1.1);
    l.night = false;
    paint->paint = PaintKind::kYellow;
    paint->opacity = rng.Uniform(0.8, 0.95);
    paint->wear = rng.Uniform(0.05, 0.2);
  } else if (preset == "faded") {
    f.material = FloorMaterial::kConcrete;
    f.base = Colour(140, 140, 138) * static_cast<float>(rng.Uniform(0.9, 1.1));
    l.gain = rng.Uniform(0.8, 1.1);
    l.night = false;
    paint->opacity = rng.Uniform(0.4, 0.55);
    paint->wear = rng.Uniform(0.35, 0.5);
    paint->repainted = true;
  }
}

// The paint of a lot family, drawn from its own stream.
LotPaint SamplePaint(Random& rng, bool seeded) {
  LotPaint p;
  p.paint = seeded && rng.Bernoulli(0.25) ? PaintKind::kYellow : PaintKind::kWhite;
  p.line_width_m = rng.Uniform(0.12, 0.2);
  p.opacity = seeded ? rng.Uniform(0.5, 1.0) : rng.Uniform(0.85, 1.0);
  p.wear = seeded ? rng.Uniform(0.0, 0.4) : rng.Uniform(0.0, 0.1);
  p.entrance_line = rng.Bernoulli(0.4);
  p.stub_m = rng.Uniform(0.35, 0.7);
  p.back_line = rng.Bernoulli(0.6);
  p.repainted = seeded && rng.Bernoulli(0.15);
  p.id_place = static_cast<int>(rng.Index(3));
  p.id_height_m = rng.Uniform(0.4, 0.6);
  p.id_setback_m = rng.Uniform(0.2, 0.5);
  p.font = static_cast<int>(rng.Index(1000));
  p.bold = rng.Bernoulli(0.6);
  p.stretch = rng.Bernoulli(0.3) ? rng.Uniform(0.7, 0.9) : rng.Uniform(0.9, 1.15);
  return p;
}

// A segment's key in centimetres, the same whichever way it runs, so that
// the line two neighbouring slots share is painted once.
using SegmentKey = std::tuple<long, long, long, long>;
SegmentKey KeyOf(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const auto cm = [](double v) { return std::lround(v * 100.0); };
  std::tuple<long, long> p(cm(a.x()), cm(a.y())), q(cm(b.x()), cm(b.y()));
  if (q < p) std::swap(p, q);
  return {std::get<0>(p), std::get<1>(p), std::get<0>(q), std::get<1>(q)};
}

// Paper III-A: the lines whose corners the detector finds. Both separating
// lines and, per family, the back line; the entrance as a continuous line
// or as stubs at its two corners (T and L junctions).
void PaintSlots(const sim::World& world, const LotPaint& paint, Random& rng, Scene* lot) {
  Stroke base;
  base.width_m = paint.line_width_m;
  base.paint = paint.paint;
  base.opacity = paint.opacity;
  base.wear = paint.wear;
  base.slot_line = true;
  std::set<SegmentKey> painted;
  const auto line = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    if (!painted.insert(KeyOf(a, b)).second) return;
    Stroke s = base;
    s.a = a;
    s.b = b;
    lot->strokes.push_back(s);
  };
  for (const sim::WorldSlot& slot : world.slots) {
    const auto& c = slot.corners_map;
    line(c[1], c[2]);
    line(c[3], c[0]);
    if (paint.back_line) line(c[2], c[3]);
    const double entrance_m = (c[1] - c[0]).norm();
    if (paint.entrance_line) {
      line(c[0], c[1]);
    } else if (entrance_m > 1e-6) {
      const Eigen::Vector2d e = (c[1] - c[0]) / entrance_m;
      const double stub = std::min(paint.stub_m, entrance_m / 2);
      line(c[0], c[0] + e * stub);
      line(c[1], c[1] - e * stub);
    }
    if (paint.repainted) {
      // The ghost of an older layout: separating lines shifted along the
      // row, burnt off or painted over.
      const Eigen::Vector2d along = (c[1] - c[0]).normalized() * rng.Uniform(0.3, 0.7);
      Stroke ghost = base;
      ghost.a = c[0] + along;
      ghost.b = c[3] + along;
      ghost.opacity = rng.Uniform(0.12, 0.3);
      ghost.wear = 0.5;
      ghost.slot_line = false;
      lot->strokes.insert(lot->strokes.begin(), ghost);  // under today's lines
    }
  }
}

// The painted IDs at the family's place, in its font; a worn ID (the
// world's id_legible false) faded and flaked beyond reading.
void PaintIds(const sim::World& world, const LotPaint& paint, Random& rng, Scene* lot) {
  for (size_t k = 0; k < world.slots.size(); ++k) {
    const sim::WorldSlot& slot = world.slots[k];
    if (slot.painted_id.empty()) continue;
    const auto& c = slot.corners_map;
    const Eigen::Vector2d mid = (c[0] + c[1]) / 2;
    const Eigen::Vector2d up = ((c[2] + c[3]) / 2 - mid).normalized();  // into the slot
    const Eigen::Vector2d reading(up.y(), -up.x());  // upright for a reader in the aisle
    FloorText text;
    text.text = slot.painted_id;
    text.height_m = paint.id_height_m * rng.Uniform(0.97, 1.03);
    text.font = paint.font;
    text.bold = paint.bold;
    text.stretch = paint.stretch;
    text.paint = paint.paint;
    text.opacity = std::min(1.0, paint.opacity * rng.Uniform(0.9, 1.1));
    text.wear = paint.wear * rng.Uniform(0.5, 1.2);
    if (!slot.id_legible) {
      text.opacity = std::min(text.opacity, 0.3);
      text.wear = std::max(text.wear, 0.7);
    }
    text.slot = static_cast<int>(k);
    const double est_width =
        0.6 * text.height_m * text.stretch * static_cast<double>(text.text.size());
    switch (paint.id_place) {
      case 1:
        text.center = mid + up * (paint.id_setback_m + text.height_m / 2);
        text.right = -reading;
        break;
      case 2: {
        // Along the separating line at corner 0, reading into the slot.
        const double half_width = (c[1] - c[0]).norm() / 2;
        const double side =
            std::max(0.0, half_width - paint.line_width_m - 0.1 - text.height_m / 2);
        text.center =
            mid + up * (paint.id_setback_m + est_width / 2) - (c[1] - c[0]).normalized() * side;
        text.right = up;
        break;
      }
      default:
        text.center = mid + up * (paint.id_setback_m + text.height_m / 2);
        text.right = reading;
        break;
    }
    lot->texts.push_back(text);
  }
}

Colour GreyColour(double level) {
  const auto v = static_cast<float>(level);
  return {v, v, v};
}

// The walls and pillars as solids reaching the ceiling, and the tags on
// them (paper III-B).
void AddStructures(const sim::World& world, Random& rng, Scene* lot) {
  const Colour wall_colour = GreyColour(rng.Uniform(110, 170));
  for (const sim::WorldWall& w : world.walls) {
    const Eigen::Vector2d d = w.b_map - w.a_map;
    const double length = d.norm();
    if (length < 1e-6) continue;
    Solid wall;
    wall.shape = SolidShape::kBox;
    // Its face on the segment, its thickness behind the side tags face.
    wall.center = (w.a_map + w.b_map) / 2 - w.normal_map * (kWallThicknessM / 2);
    wall.yaw_rad = std::atan2(d.y(), d.x());
    wall.half_x = length / 2;
    wall.half_y = kWallThicknessM / 2;
    wall.z1 = kCeilingM;
    wall.colour = wall_colour;
    lot->solids.push_back(wall);
  }
  const Colour pillar_colour = GreyColour(rng.Uniform(130, 190));
  for (const sim::WorldPillar& p : world.pillars) {
    Solid pillar;
    pillar.shape = SolidShape::kBox;
    pillar.center = p.center_map;
    pillar.half_x = pillar.half_y = p.half_size_m;
    pillar.z1 = kCeilingM;
    pillar.colour = pillar_colour;
    pillar.stripes = true;  // hazard stripes round the foot
    lot->solids.push_back(pillar);
  }
  for (const sim::WorldTag& t : world.tags) {
    WallTag tag;
    tag.tag_id = t.tag_id;
    tag.normal_yaw_rad = t.normal_yaw_rad;
    tag.center = t.p_map + Heading(t.normal_yaw_rad) * kTagStandOffM;
    tag.z_center_m = kTagCentreHeightM;
    tag.size_m = t.size_m;
    lot->tags.push_back(tag);
  }
}

// Parked cars in a share of the slots, along the slot's axis, nose in or
// out.
void AddParkedCars(const sim::World& world, double share, std::uint64_t seed, Scene* lot) {
  Random rng = Random::Derive(seed, kCarsTag);
  for (size_t k = 0; k < world.slots.size(); ++k) {
    const bool parked = rng.Bernoulli(share);
    const std::uint64_t car_seed = rng.Index(1ull << 40);
    const double jitter_along = rng.Gaussian(0.12), jitter_across = rng.Gaussian(0.06);
    const double yaw_jitter = rng.Gaussian(0.03);
    const bool nose_in = rng.Bernoulli(0.6);
    if (!parked) continue;
    const auto& c = world.slots[k].corners_map;
    const Eigen::Vector2d mid = (c[0] + c[1]) / 2, back = (c[2] + c[3]) / 2;
    const Eigen::Vector2d axis = (back - mid).normalized();
    const Eigen::Vector2d across(-axis.y(), axis.x());
    const Eigen::Vector2d centre =
        (c[0] + c[1] + c[2] + c[3]) / 4 + axis * jitter_along + across * jitter_across;
    const double yaw = std::atan2(axis.y(), axis.x()) + yaw_jitter + (nose_in ? 0.0 : kPi);
    AddParkedCar(car_seed, centre, yaw, lot);
  }
}

// Dirt over the floor by area: stains, tyre marks, cracks, patches,
// manholes, grates, arrows; puddles where the look is wet.
void AddDirt(const Extent& extent, bool outdoor, double puddles_per_100m2, Random& rng,
             Scene* lot) {
  const Eigen::Vector2d size = extent.max - extent.min;
  const double hundreds = size.x() * size.y() / 100.0;
  const auto add = [&](DecalKind kind, double per_100m2, double lmin, double lmax, double wmin,
                       double wmax) {
    const int count = static_cast<int>(std::lround(per_100m2 * hundreds * rng.Uniform(0.7, 1.3)));
    for (int i = 0; i < count; ++i) {
      Decal d;
      d.kind = kind;
      d.center = extent.min + Eigen::Vector2d(rng.Uniform(0, size.x()), rng.Uniform(0, size.y()));
      d.yaw_rad = rng.Uniform(-kPi, kPi);
      d.length_m = rng.Uniform(lmin, lmax);
      d.width_m = rng.Uniform(wmin, wmax);
      d.strength = rng.Uniform(0.3, 1.0);
      d.seed = rng.Index(1ull << 40);
      lot->decals.push_back(d);
    }
  };
  add(DecalKind::kPatch, 0.1, 1.0, 4.0, 0.8, 3.0);
  add(DecalKind::kDirt, 0.6, 1.0, 4.0, 0.5, 2.0);
  add(DecalKind::kOilStain, 1.5, 0.2, 1.0, 0.2, 0.8);
  add(DecalKind::kTyreMark, 1.0, 1.5, 5.0, 0.15, 0.25);
  add(DecalKind::kCrack, outdoor ? 0.8 : 0.4, 0.5, 3.0, 0.01, 0.03);
  add(DecalKind::kPuddle, puddles_per_100m2, 0.5, 2.5, 0.4, 1.5);
  add(DecalKind::kManhole, 0.05, 0.6, 0.9, 0.6, 0.9);
  add(DecalKind::kGrate, 0.05, 0.3, 0.8, 0.3, 0.5);
  if (outdoor) add(DecalKind::kLeaves, 0.3, 1.0, 3.0, 0.5, 2.0);
}

struct DrawnLook {
  LotPaint paint;
  Look look;
  bool outdoor = false;
};

// The family's paint and the look, each from its own stream of the seed.
DrawnLook DrawLook(const LotLook& look) {
  DrawnLook out;
  Random paint_rng = Random::Derive(look.seed, kPaintTag);
  out.paint = SamplePaint(paint_rng, look.preset == "seed");
  Random look_rng = Random::Derive(look.seed, kLookTag);
  out.outdoor = look.preset == "outdoor" || (look.preset == "seed" && look_rng.Bernoulli(0.35));
  out.look = SampleLook(MixSeed(look.seed, kLookTag), out.outdoor);
  ApplyPreset(look.preset, look_rng, &out.look, &out.paint);
  // The front camera is a camera of its own, not one of the surround-view
  // unit's: its own exposure (a fisheye's offset, up to twice too bright,
  // clips the tags' white, and their corners' fit then shrinks the tags:
  // 1.5 % too far at 17 m), no coarse sensor, its own focus and lens.
  CameraLook& front = out.look.front_camera;
  front.exposure = 1.0;
  front.sensor_scale = 1.0;
  front.defocus_px = std::min(front.defocus_px, 0.5);
  front.vignetting = std::min(front.vignetting, 0.3);
  return out;
}

}  // namespace

bool LotLook::IsValid(std::string* error) const {
  const auto fail = [error](const std::string& what) {
    if (error != nullptr) *error = what;
    return false;
  };
  const std::vector<std::string>& names = LotPresetNames();
  if (preset != "seed" && std::find(names.begin(), names.end(), preset) == names.end()) {
    std::string known = "seed";
    for (const std::string& n : names) known += ", " + n;
    return fail("unknown look '" + preset + "' (known: " + known + ")");
  }
  if (!(parked_share == -1.0 || (parked_share >= 0.0 && parked_share <= 1.0))) {  // NaN fails
    return fail("parked_share must be in [0, 1], or -1: drawn");
  }
  return true;
}

const std::vector<std::string>& LotPresetNames() {
  // The scenario's looks (sim::LookNames) but the grey renderer's and the
  // seeded one.
  static const std::vector<std::string> kNames = [] {
    std::vector<std::string> names;
    for (const std::string& n : sim::LookNames()) {
      if (n != "grey" && n != "seed") names.push_back(n);
    }
    return names;
  }();
  return kNames;
}

Scene BuildLotScene(const sim::World& world, const LotLook& look) {
  std::string error;
  if (!look.IsValid(&error)) throw std::invalid_argument("lot look: " + error);
  Scene lot;
  lot.seed = look.seed;
  const DrawnLook drawn = DrawLook(look);
  const LotPaint& paint = drawn.paint;
  const Look& sampled = drawn.look;
  const bool outdoor = drawn.outdoor;
  Random paint_rng = Random::Derive(look.seed, kPaintTag + 1);
  lot.floor = sampled.floor;
  lot.light = sampled.light;
  lot.cameras = sampled.cameras;
  lot.front_camera = sampled.front_camera;

  Extent extent;
  for (const sim::WorldSlot& s : world.slots) {
    for (const Eigen::Vector2d& c : s.corners_map) extent.Add(c);
  }
  for (const sim::WorldWall& w : world.walls) {
    extent.Add(w.a_map);
    extent.Add(w.b_map);
  }
  for (const sim::WorldPillar& p : world.pillars) extent.Add(p.center_map);
  if (extent.min.x() > extent.max.x()) extent.Add(Eigen::Vector2d::Zero());

  PaintSlots(world, paint, paint_rng, &lot);
  PaintIds(world, paint, paint_rng, &lot);
  Random walls_rng = Random::Derive(look.seed, kWallsTag);
  AddStructures(world, walls_rng, &lot);
  const double share = look.parked_share >= 0
                           ? look.parked_share
                           : Random::Derive(look.seed, kCarsTag + 1).Uniform(0.3, 0.7);
  AddParkedCars(world, share, look.seed, &lot);
  Random dirt_rng = Random::Derive(look.seed, kDirtTag);
  const double puddles = look.preset == "underground" ? 1.0 : (outdoor ? 0.15 : 0.05);
  AddDirt(extent, outdoor, puddles, dirt_rng, &lot);
  return lot;
}

}  // namespace parkslam::scene
