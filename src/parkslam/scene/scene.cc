#include "parkslam/scene/scene.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "parkslam/common/angles.h"
#include "parkslam/common/random.h"

namespace parkslam::scene {
namespace {

// Streams of the sampler, so that one part drawing more does not shift
// another.
enum StreamTag : std::uint64_t {
  kRowsTag = 0x5c1,
  kFloorTag,
  kDecalsTag,
  kSolidsTag,
  kLightTag,
  kCamerasTag,
  kTextTag,
};

// Where the lot is drawn: a little beyond the 10 m x 10 m top view around
// the car (centred 1.4 m ahead of the rear axle).
constexpr double kViewCenterX = 1.4;
constexpr double kRowHalfLengthM = 9.0;  // junctions are laid out this far each way

Eigen::Vector2d Rot90(const Eigen::Vector2d& v) { return {-v.y(), v.x()}; }
Eigen::Vector2d Dir(double yaw) { return {std::cos(yaw), std::sin(yaw)}; }

template <typename T>
const T& Pick(Random& rng, const std::vector<T>& items) {
  return items[rng.Index(items.size())];
}

// A weighted choice: the index of the chosen weight.
int Choose(Random& rng, std::initializer_list<double> weights) {
  double total = 0.0;
  for (double w : weights) total += w;
  double r = rng.Uniform() * total;
  int i = 0;
  for (double w : weights) {
    if (r < w) return i;
    r -= w;
    ++i;
  }
  return i - 1;
}

Colour Grey(double level) {
  const float l = static_cast<float>(level);
  return {l, l, l};
}

// Multiplies a grey level by a small random tint.
Colour Tinted(Random& rng, double level, double tint) {
  return {static_cast<float>(level * (1.0 + rng.Uniform(-tint, tint))),
          static_cast<float>(level * (1.0 + rng.Uniform(-tint, tint))),
          static_cast<float>(level * (1.0 + rng.Uniform(-tint, tint)))};
}

// Slot IDs as real lots paint them: 1 to 4 characters, digits and letters.
// Seven-segment rows paint digits only, 1 to 3 of them, as the default lot.
std::string SampleId(Random& rng, int row_letter, int number, bool digits_only) {
  const char letter = static_cast<char>('A' + row_letter % 26);
  char text[16];
  const int style = Choose(rng, {0.3, 0.25, 0.12, 0.12, 0.08, 0.08, 0.05});
  if (digits_only) {
    const int width = 1 + style % 3;
    std::snprintf(text, sizeof(text), "%0*d", width,
                  number % (width == 1   ? 10
                            : width == 2 ? 100
                                         : 1000));
    return text;
  }
  switch (style) {
    case 0:
      std::snprintf(text, sizeof(text), "%d", number % 1000);
      break;
    case 1:
      std::snprintf(text, sizeof(text), "%d", 10 + number % 90);
      break;
    case 2:
      std::snprintf(text, sizeof(text), "%c%d", letter, number % 100);
      break;
    case 3:
      std::snprintf(text, sizeof(text), "%c%02d", letter, number % 100);
      break;
    case 4:
      std::snprintf(text, sizeof(text), "%c-%02d", letter, number % 100);
      break;
    case 5:
      std::snprintf(text, sizeof(text), "%03d", number % 1000);
      break;
    default:
      std::snprintf(text, sizeof(text), "%d%c", number % 100, letter);
      break;
  }
  return text;
}

struct RowStyle {
  SlotKind kind = SlotKind::kPerpendicular;
  double line_width_m = 0.12;
  PaintKind paint = PaintKind::kWhite;
  double opacity = 1.0;
  double wear = 0.0;
  int entrance = 0;  // 0: continuous line, 1: stubs at the junctions, 2: open (no marking points)
  double stub_m = 0.5;
  bool back_line = false;
  bool ids = true;
  int id_placement = 0;  // 0: inside, read from the aisle; 1: inside, read from the slot; 2: along
                         // the separating line; 3: in the aisle
  double id_height_m = 0.5;
  double id_setback_m = 0.3;
  int font = 0;
  bool seven_segment = false;
  bool bold = true, stencil = false;
  double stretch = 1.0;
  PaintKind id_paint = PaintKind::kWhite;
  double car_probability = 0.5;
  bool pillars = false, wall = false, wheel_stops = false;
  bool repainted = false;
};

RowStyle SampleRowStyle(Random& rng, const SceneSamplerOptions& options, bool outdoor) {
  RowStyle s;
  const int kind = Choose(rng, {0.6, 0.2, 0.2});
  s.kind = static_cast<SlotKind>(kind);
  s.line_width_m = std::clamp(0.08 + std::abs(rng.Gaussian(0.04)), 0.08, 0.25);
  s.paint = rng.Bernoulli(0.75) ? PaintKind::kWhite : PaintKind::kYellow;
  s.opacity = rng.Bernoulli(0.15) ? rng.Uniform(0.4, 0.7) : rng.Uniform(0.7, 1.0);
  s.wear = rng.Bernoulli(0.35) ? rng.Uniform(0.0, 0.5) : rng.Uniform(0.0, 0.1);
  s.entrance = Choose(rng, {0.5, 0.4, 0.1});
  s.stub_m = rng.Uniform(0.3, 0.9);
  s.back_line = rng.Bernoulli(0.5);
  s.ids = rng.Bernoulli(0.65);
  s.id_placement = Choose(rng, {0.45, 0.2, 0.2, 0.15});
  s.id_height_m = rng.Uniform(0.25, 0.55);
  s.id_setback_m = rng.Uniform(0.1, 0.6);
  s.font = static_cast<int>(rng.Index(1000));
  s.seven_segment = s.font < options.seven_segment_share * 1000;
  s.bold = rng.Bernoulli(0.4);
  s.stencil = rng.Bernoulli(0.2);
  s.stretch = rng.Bernoulli(0.4) ? rng.Uniform(0.6, 0.9) : rng.Uniform(0.9, 1.3);
  if (s.seven_segment) {
    // Painted as the default lot paints them: plain segments, no bridges.
    s.bold = s.stencil = false;
    s.stretch = std::clamp(s.stretch, 0.85, 1.15);
  }
  s.id_paint = rng.Bernoulli(0.6)
                   ? s.paint
                   : Pick(rng, std::vector<PaintKind>{PaintKind::kWhite, PaintKind::kYellow,
                                                      PaintKind::kYellow});
  s.car_probability = rng.Uniform(0.0, options.parked_car_probability_max);
  s.pillars = !outdoor && rng.Bernoulli(0.35);
  s.wall = !outdoor && rng.Bernoulli(0.3);
  s.wheel_stops = rng.Bernoulli(0.2);
  s.repainted = rng.Bernoulli(0.12);
  return s;
}

bool InsideEgo(const Eigen::Vector2d& p, const SceneSamplerOptions& o, double margin_m) {
  return p.x() > -o.ego_rear_overhang_m - margin_m &&
         p.x() < o.ego_length_m - o.ego_rear_overhang_m + margin_m &&
         std::abs(p.y()) < o.ego_width_m / 2 + margin_m;
}

// Whether an oriented box (centre, yaw, half extents) comes within margin
// of the ego car: tested on its corners and centre, enough for the sizes
// here (the car is larger than every solid but walls, which are tested
// along their length).
bool BoxNearEgo(const Eigen::Vector2d& c, double yaw, double hx, double hy,
                const SceneSamplerOptions& o, double margin_m) {
  const Eigen::Vector2d ax = Dir(yaw), ay = Rot90(ax);
  const int steps = std::max(1, static_cast<int>(std::ceil(hx / 0.5)));
  for (int i = -steps; i <= steps; ++i) {
    for (int j = -1; j <= 1; ++j) {
      const Eigen::Vector2d p = c + ax * (hx * i / steps) + ay * (hy * j);
      if (InsideEgo(p, o, margin_m)) return true;
    }
  }
  return false;
}

void AddCar(Random& rng, const Eigen::Vector2d& center, double yaw, Scene* scene) {
  static const std::vector<Colour> kCarColours = {
      {235, 235, 235}, {205, 205, 200}, {160, 160, 160}, {40, 40, 40},   {25, 25, 30},
      {40, 40, 170},   {150, 70, 30},   {60, 110, 60},   {90, 150, 200}, {70, 40, 20},
      {180, 180, 190}, {30, 60, 140},   {120, 120, 125}, {200, 200, 210}};
  const double length = rng.Uniform(4.0, 5.1), width = rng.Uniform(1.65, 1.95);
  const Colour colour = Pick(rng, kCarColours) * static_cast<float>(rng.Uniform(0.85, 1.1));
  const Eigen::Vector2d ax = Dir(yaw), ay = Rot90(ax);
  const double body_top = rng.Uniform(0.75, 0.95), roof = rng.Uniform(1.35, 1.6);
  Solid body;
  body.shape = SolidShape::kBox;
  body.center = center;
  body.yaw_rad = yaw;
  body.half_x = length / 2;
  body.half_y = width / 2;
  body.z0 = 0.25;
  body.z1 = body_top;
  // Seen from above a car's plan is rounded at its four corners, not a
  // box's (a share of its width, so that no draw is added).
  body.corner_radius_m = 0.2 * width;
  body.colour = colour;
  body.material = SolidMaterial::kPaint;
  scene->solids.push_back(body);
  Solid cabin = body;
  cabin.center = center + ax * rng.Uniform(-0.35, 0.05) * length / 2;
  cabin.half_x = length * rng.Uniform(0.24, 0.32);
  cabin.half_y = width / 2 - 0.1;
  cabin.corner_radius_m = 0.3;
  cabin.z0 = body_top;
  cabin.z1 = roof;
  cabin.material = SolidMaterial::kGlass;
  scene->solids.push_back(cabin);
  for (int sx = -1; sx <= 1; sx += 2) {
    for (int sy = -1; sy <= 1; sy += 2) {
      Solid tyre;
      tyre.shape = SolidShape::kBox;
      // Wheels stand a little proud of the body's sides, so that the
      // fisheyes see their sidewalls and rims below the body.
      tyre.center = center + ax * (sx * (length / 2 - 0.85)) + ay * (sy * (width / 2 - 0.09));
      tyre.yaw_rad = yaw;
      tyre.half_x = 0.31;
      tyre.half_y = 0.11;
      tyre.z0 = 0.0;
      tyre.z1 = 0.62;
      tyre.colour = Grey(30);
      tyre.material = SolidMaterial::kTyre;
      tyre.casts_shadow = false;
      scene->solids.push_back(tyre);
    }
  }
}

// Where one row of slots lies: its direction u, the normal n into the slots,
// the junctions along the entrance line (k_first..k_last) and the
// separating lines from them.
struct RowLayout {
  Eigen::Vector2d u, n, origin, sep;
  double depth = 0.0, step = 0.0, angle_deg = 90.0, sep_length = 0.0, phase = 0.0;
  int k_first = 0, k_last = 0;
  bool starts = false, ends = false;  // the row's ends within the lot drawn

  Eigen::Vector2d Junction(int k) const { return Eigen::Vector2d(origin + u * (phase + k * step)); }
  // Half a line of width w, measured along the row where it meets a
  // separating line.
  double HalfAlongRow(double w) const { return w / 2 / std::max(0.3, std::abs(sep.dot(n))); }
};

RowLayout SampleRowLayout(Random& rng, const RowStyle& s, bool left, double row_yaw,
                          double offset_m) {
  RowLayout r;
  r.u = Dir(row_yaw);
  // Into the slots: away from the car.
  r.n = Rot90(r.u);
  if (!left) r.n = -r.n;
  r.origin = Eigen::Vector2d(kViewCenterX, 0.0) + r.n * offset_m;
  r.sep = r.n;  // separating line direction, into the slot
  switch (s.kind) {
    case SlotKind::kPerpendicular:
      r.step = rng.Uniform(2.2, 3.0);
      r.depth = rng.Uniform(4.6, 5.6);
      break;
    case SlotKind::kParallel:
      r.step = rng.Uniform(5.2, 7.0);
      r.depth = rng.Uniform(2.0, 2.6);
      break;
    case SlotKind::kAngled: {
      r.angle_deg = rng.Uniform(40.0, 75.0);
      const double phi = DegToRad(r.angle_deg);
      const double lean = rng.Bernoulli(0.5) ? 1.0 : -1.0;
      r.sep = (r.n * std::sin(phi) + r.u * (lean * std::cos(phi))).normalized();
      r.step = rng.Uniform(2.3, 2.8) / std::sin(phi);
      r.depth = rng.Uniform(4.5, 5.3);
      break;
    }
  }
  r.sep_length = r.depth / std::max(0.3, std::abs(r.sep.dot(r.n)));
  r.phase = rng.Uniform(0.0, r.step);
  r.k_first = static_cast<int>(std::floor((-kRowHalfLengthM - r.phase) / r.step));
  r.k_last = static_cast<int>(std::ceil((kRowHalfLengthM - r.phase) / r.step));
  if (rng.Bernoulli(0.25)) {
    r.k_first = static_cast<int>(std::floor(rng.Uniform(-5.0, 2.0) / r.step));
    r.starts = true;
  }
  if (rng.Bernoulli(0.25)) {
    r.k_last =
        std::max(r.k_first + 1, static_cast<int>(std::ceil(rng.Uniform(-1.0, 6.0) / r.step)));
    r.ends = true;
  }
  return r;
}

// The row's paint: separating lines, entrance stubs or line, back line and
// the ghost of a repainted layout; the marking points at the junctions.
// Returns each junction's marking point (-1: none), from k_first.
std::vector<int> PaintRowLines(Random& rng, const RowStyle& s, const RowLayout& r,
                               const Stroke& base, Scene* scene) {
  const double w = s.line_width_m;
  std::vector<int> mark_of(static_cast<size_t>(r.k_last - r.k_first + 1), -1);
  for (int k = r.k_first; k <= r.k_last; ++k) {
    const Eigen::Vector2d p = r.Junction(k);
    Stroke line = base;
    // The separating line starts on the entrance line's far edge when one is
    // painted (a T or L), at the junction otherwise.
    line.a = p;
    line.b = p + r.sep * r.sep_length;
    scene->strokes.push_back(line);
    if (s.entrance == 1) {
      Stroke stub = base;
      const bool first = r.starts && k == r.k_first, last = r.ends && k == r.k_last;
      const double half = r.HalfAlongRow(w);
      stub.a = p - r.u * (first ? half : s.stub_m);
      stub.b = p + r.u * (last ? half : s.stub_m);
      scene->strokes.push_back(stub);
    }
    if (s.entrance != 2) {
      MarkingPoint mark;
      mark.p_vehicle = p;
      mark.direction = r.sep;
      mark.is_t = !((r.starts && k == r.k_first) || (r.ends && k == r.k_last));
      mark_of[static_cast<size_t>(k - r.k_first)] = static_cast<int>(scene->marks.size());
      scene->marks.push_back(mark);
    }
  }
  const double half_end = r.HalfAlongRow(w);
  if (s.entrance == 0) {
    Stroke line = base;
    line.a = r.Junction(r.k_first) - r.u * (r.starts ? half_end : 1.0);
    line.b = r.Junction(r.k_last) + r.u * (r.ends ? half_end : 1.0);
    scene->strokes.push_back(line);
  }
  if (s.back_line) {
    Stroke line = base;
    line.a = r.Junction(r.k_first) + r.sep * r.sep_length - r.u * (r.starts ? half_end : 1.0);
    line.b = r.Junction(r.k_last) + r.sep * r.sep_length + r.u * (r.ends ? half_end : 1.0);
    scene->strokes.push_back(line);
  }
  if (s.repainted) {
    // The ghost of an older layout, shifted along the row.
    const double shift = rng.Uniform(0.2, 0.8) * (rng.Bernoulli(0.5) ? 1 : -1);
    for (int k = r.k_first; k <= r.k_last; ++k) {
      Stroke ghost = base;
      ghost.a = r.Junction(k) + r.u * shift;
      ghost.b = ghost.a + r.sep * r.sep_length;
      ghost.opacity = rng.Uniform(0.1, 0.3);
      ghost.wear = 0.5;
      ghost.slot_line = false;
      scene->strokes.push_back(ghost);
    }
  }
  return mark_of;
}

// The painted ID of the slot whose entrance has its middle at `mid`
// (slot_index -1: the slot has no marking points).
void AddSlotId(Random& rng, const RowStyle& s, const RowLayout& r, const Eigen::Vector2d& mid,
               int number, int row_letter, int slot_index, Scene* scene) {
  const double w = s.line_width_m;
  const Eigen::Vector2d& sep = r.sep;
  const Eigen::Vector2d reading(sep.y(), -sep.x());  // text up along sep, into the slot
  FloorText text;
  text.text = SampleId(rng, row_letter, number, s.seven_segment);
  text.height_m = s.id_height_m * rng.Uniform(0.95, 1.05);
  text.font = s.font;
  text.seven_segment = s.seven_segment;
  text.bold = s.bold;
  text.stencil = s.stencil;
  text.stretch = s.stretch;
  text.paint = s.id_paint;
  text.opacity = std::min(1.0, s.opacity * rng.Uniform(0.8, 1.2));
  text.wear = s.wear * rng.Uniform(0.5, 1.5);
  text.slot = slot_index;
  const double est_width =
      0.6 * text.height_m * text.stretch * static_cast<double>(text.text.size());
  switch (s.id_placement) {
    case 0:
      text.center = mid + sep * (s.id_setback_m + text.height_m / 2);
      text.right = reading;
      break;
    case 1:
      text.center = mid + sep * (s.id_setback_m + text.height_m / 2);
      text.right = -reading;
      break;
    case 2: {
      const double side = std::min(r.step / 2 - w - 0.1 - text.height_m / 2, r.step / 2 - 0.25);
      text.center = mid + sep * (s.id_setback_m + est_width / 2) - r.u * side;
      text.right = rng.Bernoulli(0.5) ? sep : Eigen::Vector2d(-sep);
      break;
    }
    default:
      text.center = mid - sep * (0.25 + text.height_m / 2);
      text.right = reading;
      break;
  }
  if (slot_index >= 0) {
    Slot& slot = scene->slots[static_cast<size_t>(slot_index)];
    slot.id = text.text;
    slot.id_legible = text.opacity > 0.35 && text.wear < 0.5;
  }
  scene->texts.push_back(text);
}

// The slot between junctions k and k + 1: the slot itself when both have
// marking points, its ID, a parked car, a wheel stop.
void AddRowSlot(Random& rng, const SceneSamplerOptions& options, const RowStyle& s,
                const RowLayout& r, const std::vector<int>& mark_of, int k, int first_number,
                int row_letter, Scene* scene) {
  const Eigen::Vector2d& u = r.u;
  const Eigen::Vector2d& sep = r.sep;
  const bool a_first = Rot90(u).dot(r.n) > 0;  // slot left of a->b in the vehicle frame
  const Eigen::Vector2d p0 = r.Junction(k), p1 = r.Junction(k + 1);
  const Eigen::Vector2d mid = (p0 + p1) / 2;
  const int m0 = mark_of[static_cast<size_t>(k - r.k_first)];
  const int m1 = mark_of[static_cast<size_t>(k + 1 - r.k_first)];
  int slot_index = -1;
  if (m0 >= 0 && m1 >= 0) {
    Slot slot;
    slot.a = a_first ? m0 : m1;
    slot.b = a_first ? m1 : m0;
    slot.kind = s.kind;
    slot.angle_deg = r.angle_deg;
    slot.depth_m = r.sep_length;
    slot_index = static_cast<int>(scene->slots.size());
    scene->slots.push_back(slot);
  }
  const Eigen::Vector2d reading(sep.y(), -sep.x());  // text up along sep, into the slot
  const bool has_id = s.ids && rng.Bernoulli(0.9);
  if (has_id) {
    AddSlotId(rng, s, r, mid, first_number + (k - r.k_first), row_letter, slot_index, scene);
  }
  const Eigen::Vector2d slot_center = mid + sep * (r.sep_length / 2);
  if (rng.Bernoulli(s.car_probability)) {
    const double car_yaw = std::atan2(s.kind == SlotKind::kParallel ? u.y() : sep.y(),
                                      s.kind == SlotKind::kParallel ? u.x() : sep.x()) +
                           rng.Gaussian(0.04) + (rng.Bernoulli(0.5) ? kPi : 0.0);
    const Eigen::Vector2d center = slot_center + sep * rng.Gaussian(0.15) + u * rng.Gaussian(0.1);
    if (!BoxNearEgo(center, car_yaw, 2.6, 1.0, options, 0.4)) AddCar(rng, center, car_yaw, scene);
  }
  if (s.wheel_stops && s.kind != SlotKind::kParallel) {
    Decal stop;
    stop.kind = DecalKind::kWheelStop;
    stop.center = mid + sep * (r.sep_length - 0.7);
    stop.yaw_rad = std::atan2(reading.y(), reading.x());
    stop.length_m = rng.Uniform(1.4, 1.9);
    stop.width_m = rng.Uniform(0.12, 0.2);
    stop.seed = rng.Index(1u << 30);
    scene->decals.push_back(stop);
  }
}

// Pillars behind every second or third junction.
void AddRowPillars(Random& rng, const SceneSamplerOptions& options, const RowLayout& r,
                   double row_yaw, Scene* scene) {
  const int every = 2 + static_cast<int>(rng.Index(2));
  const double size = rng.Uniform(0.5, 0.8);
  const Colour colour = Tinted(rng, rng.Uniform(150, 230), 0.05);
  for (int k = r.k_first; k <= r.k_last; ++k) {
    if (((k % every) + every) % every != 0) continue;
    Solid pillar;
    pillar.shape = SolidShape::kBox;
    pillar.center = r.Junction(k) + r.sep * (r.sep_length + size / 2 + 0.1);
    pillar.yaw_rad = row_yaw;
    pillar.half_x = pillar.half_y = size / 2;
    pillar.z0 = 0;
    pillar.z1 = 3.0;
    pillar.colour = colour;
    pillar.stripes = rng.Bernoulli(0.6);
    if (!BoxNearEgo(pillar.center, pillar.yaw_rad, size / 2, size / 2, options, 0.3)) {
      scene->solids.push_back(pillar);
    }
  }
}

// A wall behind the row's slots.
void AddRowWall(Random& rng, const SceneSamplerOptions& options, const RowLayout& r, double row_yaw,
                Scene* scene) {
  Solid wall;
  wall.shape = SolidShape::kBox;
  wall.center = r.origin + r.n * (r.depth + rng.Uniform(0.4, 1.2));
  wall.yaw_rad = row_yaw;
  wall.half_x = 20.0;
  wall.half_y = 0.1;
  wall.z0 = 0;
  wall.z1 = 3.0;
  wall.colour = Tinted(rng, rng.Uniform(140, 220), 0.08);
  wall.stripes = rng.Bernoulli(0.3);
  if (!BoxNearEgo(wall.center, wall.yaw_rad, wall.half_x, wall.half_y, options, 0.5)) {
    scene->solids.push_back(wall);
  }
}

// One row of slots: junctions along the entrance line, their separating
// lines, the entrance line (continuous or stubs), an optional back line,
// painted IDs, parked cars, pillars, wheel stops.
void AddRow(Random& rng, const SceneSamplerOptions& options, bool left, bool outdoor,
            double row_yaw, double offset_m, int row_letter, Scene* scene) {
  const RowStyle s = SampleRowStyle(rng, options, outdoor);
  const RowLayout r = SampleRowLayout(rng, s, left, row_yaw, offset_m);
  Stroke base;
  base.width_m = s.line_width_m;
  base.paint = s.paint;
  base.opacity = s.opacity;
  base.wear = s.wear;
  base.slot_line = true;
  const std::vector<int> mark_of = PaintRowLines(rng, s, r, base, scene);

  // Slots between consecutive junctions, with their IDs and cars.
  const int first_number = static_cast<int>(rng.Index(300)) + 1;
  for (int k = r.k_first; k < r.k_last; ++k) {
    AddRowSlot(rng, options, s, r, mark_of, k, first_number, row_letter, scene);
  }
  if (s.pillars) AddRowPillars(rng, options, r, row_yaw, scene);
  if (s.wall) AddRowWall(rng, options, r, row_yaw, scene);
}

void SampleFloor(Random& rng, bool outdoor, Scene* scene) {
  Floor& f = scene->floor;
  if (outdoor) {
    f.material = static_cast<FloorMaterial>(
        std::array<int, 4>{0, 2, 3, 4}[static_cast<size_t>(Choose(rng, {0.25, 0.35, 0.3, 0.1}))]);
  } else {
    f.material = static_cast<FloorMaterial>(Choose(rng, {0.45, 0.3, 0.15, 0.0, 0.1}));
  }
  f.texture = rng.Uniform(0.5, 1.5);
  f.blotches = rng.Uniform(0.3, 1.6);
  f.pattern_yaw_rad = rng.Bernoulli(0.7) ? 0.0 : rng.Uniform(-kPi / 4, kPi / 4);
  switch (f.material) {
    case FloorMaterial::kConcrete:
      f.base = Tinted(rng, rng.Uniform(95, 185), 0.06);
      // Sealed or polished concrete mirrors the lamps too, less sharply.
      f.gloss = rng.Bernoulli(0.5) ? rng.Uniform(0.1, 0.6) : 0.0;
      break;
    case FloorMaterial::kEpoxy: {
      static const std::vector<Colour> kEpoxy = {{150, 150, 150}, {120, 140, 110}, {150, 140, 120},
                                                 {170, 170, 165}, {110, 120, 100}, {130, 120, 110},
                                                 {180, 180, 175}};
      f.base = Pick(rng, kEpoxy) * static_cast<float>(rng.Uniform(0.8, 1.15));
      f.gloss = rng.Uniform(0.2, 0.8);
      f.texture = rng.Uniform(0.2, 0.6);
      break;
    }
    case FloorMaterial::kAsphalt:
      f.base = Tinted(rng, rng.Uniform(45, 105), 0.05);
      break;
    case FloorMaterial::kBricks: {
      static const std::vector<Colour> kBricks = {
          {70, 85, 140}, {120, 120, 125}, {110, 130, 150}, {90, 100, 120}, {150, 150, 150}};
      f.base = Pick(rng, kBricks) * static_cast<float>(rng.Uniform(0.8, 1.2));
      f.joint = f.base * static_cast<float>(rng.Uniform(0.5, 0.8));
      f.unit_m = rng.Uniform(0.18, 0.26);
      f.herringbone = rng.Bernoulli(0.3);
      break;
    }
    case FloorMaterial::kTiles:
      f.base = Tinted(rng, rng.Uniform(110, 190), 0.06);
      f.joint = f.base * static_cast<float>(rng.Uniform(0.55, 0.85));
      f.unit_m = rng.Uniform(0.3, 0.8);
      break;
  }
  if (outdoor && rng.Bernoulli(0.5)) {
    f.verge = true;
    const double yaw = rng.Bernoulli(0.8) ? rng.Gaussian(0.08) : rng.Uniform(-kPi, kPi);
    const Eigen::Vector2d normal = Rot90(Dir(yaw)) * (rng.Bernoulli(0.5) ? 1.0 : -1.0);
    f.verge_normal = normal;
    f.verge_point = Eigen::Vector2d(kViewCenterX, 0) + normal * rng.Uniform(2.0, 9.0);
    f.verge_gravel = rng.Bernoulli(0.25);
    f.kerb = rng.Bernoulli(0.7);
  }
}

void SampleDecals(Random& rng, bool outdoor, Scene* scene) {
  const auto random_point = [&](double spread) {
    return Eigen::Vector2d(kViewCenterX + rng.Uniform(-spread, spread),
                           rng.Uniform(-spread, spread));
  };
  const auto add = [&](DecalKind kind, int count, double lmin, double lmax, double wmin,
                       double wmax, double spread) {
    for (int i = 0; i < count; ++i) {
      Decal d;
      d.kind = kind;
      d.center = random_point(spread);
      d.yaw_rad = rng.Uniform(-kPi, kPi);
      d.length_m = rng.Uniform(lmin, lmax);
      d.width_m = rng.Uniform(wmin, wmax);
      d.strength = rng.Uniform(0.3, 1.0);
      d.seed = rng.Index(1ull << 40);
      scene->decals.push_back(d);
    }
  };
  add(DecalKind::kPatch, rng.Bernoulli(0.3) ? 1 + static_cast<int>(rng.Index(3)) : 0, 1.0, 4.0, 0.8,
      3.0, 7);
  add(DecalKind::kDirt, static_cast<int>(rng.Index(6)), 1.0, 4.0, 0.5, 2.0, 7);
  add(DecalKind::kOilStain, static_cast<int>(rng.Index(7)), 0.2, 1.0, 0.2, 0.8, 6);
  add(DecalKind::kTyreMark, static_cast<int>(rng.Index(7)), 1.5, 5.0, 0.15, 0.25, 6);
  add(DecalKind::kCrack, static_cast<int>(rng.Index(outdoor ? 5 : 3)), 0.5, 3.0, 0.01, 0.03, 7);
  add(DecalKind::kPuddle, rng.Bernoulli(0.15) ? 1 + static_cast<int>(rng.Index(2)) : 0, 0.5, 2.5,
      0.4, 1.5, 6);
  add(DecalKind::kManhole, rng.Bernoulli(0.35) ? 1 + static_cast<int>(rng.Index(2)) : 0, 0.6, 0.9,
      0.6, 0.9, 5);
  add(DecalKind::kGrate, rng.Bernoulli(0.3) ? 1 + static_cast<int>(rng.Index(2)) : 0, 0.3, 0.8, 0.3,
      0.5, 5);
  add(DecalKind::kArrow, rng.Bernoulli(0.3) ? 1 : 0, 2.0, 4.0, 0.6, 1.0, 4);
  add(DecalKind::kZebra, rng.Bernoulli(0.08) ? 1 : 0, 3.0, 5.0, 2.0, 4.0, 4);
  add(DecalKind::kSpeedBump, rng.Bernoulli(0.06) ? 1 : 0, 4.0, 8.0, 0.4, 0.6, 4);
  if (outdoor) add(DecalKind::kLeaves, static_cast<int>(rng.Index(4)), 1.0, 3.0, 0.5, 2.0, 6);
  // Lines of older layouts, burnt off or painted over: faint, anywhere.
  const int old_lines = rng.Bernoulli(0.35) ? 1 + static_cast<int>(rng.Index(4)) : 0;
  for (int i = 0; i < old_lines; ++i) {
    Stroke line;
    line.a = random_point(6.0);
    line.b = line.a + Dir(rng.Uniform(-kPi, kPi)) * rng.Uniform(1.0, 6.0);
    line.width_m = rng.Uniform(0.08, 0.2);
    line.paint = rng.Bernoulli(0.7) ? PaintKind::kWhite : PaintKind::kYellow;
    line.opacity = rng.Uniform(0.08, 0.3);
    line.wear = rng.Uniform(0.2, 0.6);
    scene->strokes.insert(scene->strokes.begin(), line);  // under today's lines
  }
}

// Lines along the aisle: a double centre line, or a dashed one.
void SampleAisleLines(Random& rng, double row_yaw, Scene* scene) {
  if (!rng.Bernoulli(0.25)) return;
  const Eigen::Vector2d u = Dir(row_yaw), n = Rot90(u);
  const Eigen::Vector2d centre = Eigen::Vector2d(kViewCenterX, 0.0) + n * rng.Uniform(-1.2, 1.2);
  Stroke line;
  line.width_m = rng.Uniform(0.08, 0.15);
  line.paint = rng.Bernoulli(0.6) ? PaintKind::kYellow : PaintKind::kWhite;
  line.opacity = rng.Uniform(0.5, 1.0);
  line.wear = rng.Uniform(0.0, 0.4);
  if (rng.Bernoulli(0.5)) {
    const double gap = rng.Uniform(0.1, 0.2) + line.width_m;
    for (const double side : {-0.5, 0.5}) {
      line.a = centre + n * (side * gap) - u * 12.0;
      line.b = centre + n * (side * gap) + u * 12.0;
      scene->strokes.push_back(line);
    }
  } else {
    const double dash = rng.Uniform(1.0, 3.0), period = dash + rng.Uniform(1.0, 3.0);
    for (double t = -12.0 + rng.Uniform(0.0, period); t < 12.0; t += period) {
      line.a = centre + u * t;
      line.b = centre + u * (t + dash);
      scene->strokes.push_back(line);
    }
  }
}

void SampleFloorTexts(Random& rng, Scene* scene) {
  static const std::vector<std::string> kWords = {
      "EXIT", "SLOW", "P", "B2", "STOP", "IN", "OUT", "5", "10", "VIP", "EV", "NO PARKING", "F1"};
  const int count = rng.Bernoulli(0.25) ? 1 : 0;
  for (int i = 0; i < count; ++i) {
    FloorText t;
    t.text = Pick(rng, kWords);
    t.center = Eigen::Vector2d(kViewCenterX + rng.Uniform(-3.0, 3.0), rng.Uniform(-1.5, 1.5));
    t.right = Dir(rng.Uniform(-kPi, kPi));
    t.height_m = rng.Uniform(0.4, 1.0);
    t.font = static_cast<int>(rng.Index(1000));
    t.bold = true;
    t.paint = rng.Bernoulli(0.6) ? PaintKind::kWhite : PaintKind::kYellow;
    t.opacity = rng.Uniform(0.4, 1.0);
    t.wear = rng.Uniform(0.0, 0.4);
    scene->texts.push_back(t);
  }
}

void SampleMovers(Random& rng, const SceneSamplerOptions& options, Scene* scene) {
  static const std::vector<Colour> kClothes = {{40, 40, 40},    {120, 60, 30}, {30, 30, 140},
                                               {200, 200, 200}, {60, 120, 60}, {90, 90, 90}};
  const int people = rng.Bernoulli(0.2) ? 1 + static_cast<int>(rng.Index(2)) : 0;
  for (int i = 0; i < people; ++i) {
    Solid p;
    p.shape = SolidShape::kCylinder;
    p.center = Eigen::Vector2d(kViewCenterX + rng.Uniform(-5, 5), rng.Uniform(-5, 5));
    if (InsideEgo(p.center, options, 0.6)) continue;
    p.half_x = rng.Uniform(0.2, 0.3);
    p.z1 = rng.Uniform(1.55, 1.9);
    p.colour = Pick(rng, kClothes);
    p.material = SolidMaterial::kMatt;
    scene->solids.push_back(p);
    Solid head = p;
    head.half_x = 0.11;
    head.z0 = p.z1;
    head.z1 = p.z1 + 0.22;
    head.colour = Colour(90, 120, 170) * static_cast<float>(rng.Uniform(0.5, 1.2));
    head.material = SolidMaterial::kSkin;
    scene->solids.push_back(head);
  }
  const int cones = rng.Bernoulli(0.1) ? 1 + static_cast<int>(rng.Index(3)) : 0;
  const Eigen::Vector2d start(kViewCenterX + rng.Uniform(-4, 4), rng.Uniform(-4, 4));
  const Eigen::Vector2d along = Dir(rng.Uniform(-kPi, kPi));
  for (int i = 0; i < cones; ++i) {
    Solid c;
    c.shape = SolidShape::kCone;
    c.center = start + along * (1.2 * i);
    if (InsideEgo(c.center, options, 0.4)) continue;
    c.half_x = rng.Uniform(0.14, 0.2);
    c.z1 = rng.Uniform(0.5, 0.75);
    c.colour = {20, 90, 240};
    c.stripes = true;
    scene->solids.push_back(c);
  }
}

void SampleLight(Random& rng, bool outdoor, Scene* scene) {
  Lighting& l = scene->light;
  l.outdoor = outdoor;
  l.seed = rng.Index(1ull << 40);
  l.patchy = rng.Uniform(0.0, 0.35);
  if (outdoor) {
    l.gain = rng.Uniform(0.85, 1.35);
    l.tint = Colour(static_cast<float>(rng.Uniform(0.85, 1.05)), 1.0f,
                    static_cast<float>(rng.Uniform(0.98, 1.15)));
    l.sun_azimuth_rad = rng.Uniform(-kPi, kPi);
    l.sun_elevation_rad = rng.Uniform(0.35, 1.2);
    l.shadow_depth = rng.Bernoulli(0.2) ? rng.Uniform(0.0, 0.2) : rng.Uniform(0.35, 0.7);
    l.trees = rng.Bernoulli(0.3) ? 1 + static_cast<int>(rng.Index(3)) : 0;
    l.pools = 0.0;
  } else {
    const int mode =
        Choose(rng, {0.45, 0.2, 0.15, 0.1, 0.1});  // normal, dim, bright, backlit, night
    l.gain = mode == 1   ? rng.Uniform(0.4, 0.7)
             : mode == 2 ? rng.Uniform(1.2, 1.6)
                         : rng.Uniform(0.75, 1.15);
    l.night = mode == 4;
    if (l.night) l.gain = rng.Uniform(0.5, 0.9);
    l.backlight = mode == 3 ? rng.Uniform(0.8, 2.5) : 0.0;
    l.backlight_dir = Dir(rng.Uniform(-kPi, kPi));
    l.tint = l.night ? Colour(0.65f, 0.9f, 1.2f)
                     : Colour(static_cast<float>(rng.Uniform(0.9, 1.12)), 1.0f,
                              static_cast<float>(rng.Uniform(0.88, 1.08)));
    l.lamp_spacing_m = rng.Uniform(4.0, 8.0);
    l.lamp_offset =
        Eigen::Vector2d(rng.Uniform(0, l.lamp_spacing_m), rng.Uniform(0, l.lamp_spacing_m));
    l.lamp_height_m = rng.Uniform(2.5, 3.5);
    l.pools = l.night ? rng.Uniform(0.6, 0.9) : rng.Uniform(0.0, 0.6);
    l.shadow_depth = rng.Uniform(0.2, 0.5);
  }
}

void SampleCameras(Random& rng, const SceneSamplerOptions& options, bool outdoor, Scene* scene) {
  // The unit's shared settings, then each camera's own deviation.
  const double seam = rng.Uniform(0.05, 0.3);
  const double noise = rng.Uniform(1.0, 5.0);
  const double vignetting = rng.Uniform(0.1, 0.6);
  const int jpeg = rng.Bernoulli(0.85) ? 95 : static_cast<int>(rng.Uniform(40, 90));
  const bool motion = rng.Bernoulli(0.2);
  const double defocus = rng.Bernoulli(0.35) ? rng.Uniform(0.4, 1.6) : 0.0;
  const int dirty =
      rng.Bernoulli(0.15)
          ? static_cast<int>(rng.Index(static_cast<std::uint64_t>(options.fisheye_cameras)))
          : -1;
  const int glare =
      outdoor && rng.Bernoulli(0.35)
          ? static_cast<int>(rng.Index(static_cast<std::uint64_t>(options.fisheye_cameras)))
          : -1;
  // Many surround-view units have coarse sensors: what they see far off
  // smears into radial streaks once fused.
  const double sensor_scale =
      rng.Bernoulli(options.coarse_sensor_share) ? rng.Uniform(0.55, 0.95) : 1.0;
  for (int c = 0; c < options.fisheye_cameras; ++c) {
    CameraLook look;
    look.sensor_scale = sensor_scale;
    look.exposure = std::exp(rng.Gaussian(seam));
    const double wb = seam * 0.4;
    look.white_balance = Colour(static_cast<float>(std::exp(rng.Gaussian(wb))), 1.0f,
                                static_cast<float>(std::exp(rng.Gaussian(wb))));
    look.vignetting = vignetting * rng.Uniform(0.8, 1.2);
    look.noise_sigma = noise * rng.Uniform(0.8, 1.2);
    look.motion_blur_px = motion ? rng.Uniform(1.0, 6.0) : 0.0;
    look.motion_angle_rad = rng.Uniform(-kPi, kPi);
    look.defocus_px = defocus * rng.Uniform(0.7, 1.3);
    look.dirt_spots = c == dirty ? 1 + static_cast<int>(rng.Index(4)) : 0;
    look.glare = c == glare ? rng.Uniform(0.5, 1.0) : 0.0;
    look.jpeg_quality = jpeg;
    look.seed = rng.Index(1ull << 40);
    scene->cameras.push_back(look);
  }
  scene->front_camera = scene->cameras.front();
  scene->front_camera.seed = rng.Index(1ull << 40);
  scene->fusion_calibration = rng.Bernoulli(0.5)
                                  ? 0
                                  : 1 + static_cast<int>(rng.Index(static_cast<std::uint64_t>(
                                            std::max(1, options.perturbed_calibrations))));
  if (options.perturbed_calibrations == 0) scene->fusion_calibration = 0;
  scene->fusion_seams =
      static_cast<int>(rng.Index(static_cast<std::uint64_t>(std::max(1, options.seam_layouts))));
  scene->top_view_jpeg_quality = static_cast<int>(rng.Uniform(55, 95));
  scene->top_view_sharpen = rng.Bernoulli(0.3) ? rng.Uniform(0.2, 0.8) : 0.0;
  scene->saturation = rng.Uniform(0.55, 1.15);
  scene->fusion_nearest =
      options.nearest_lookup_share > 0 && rng.Bernoulli(options.nearest_lookup_share);
  if (options.ray_seam_share > 0 && options.ray_seam_layouts > 0 &&
      rng.Bernoulli(options.ray_seam_share)) {
    scene->fusion_seams =
        std::max(1, options.seam_layouts) +
        static_cast<int>(rng.Index(static_cast<std::uint64_t>(options.ray_seam_layouts)));
  }
  if (options.chroma_noise_share > 0 && rng.Bernoulli(options.chroma_noise_share)) {
    const double unit = rng.Uniform(0.3, 1.0) * options.chroma_noise_max;
    for (CameraLook& look : scene->cameras) look.chroma_noise = unit * rng.Uniform(0.8, 1.2);
  }
}

}  // namespace

bool SceneSamplerOptions::IsValid(std::string* error) const {
  const auto fail = [error](const char* what) {
    if (error != nullptr) *error = what;
    return false;
  };
  if (fisheye_cameras < 1 || fisheye_cameras > 16)
    return fail("fisheye_cameras must be in [1, 16]");
  if (perturbed_calibrations < 0 || perturbed_calibrations > 64) {
    return fail("perturbed_calibrations must be in [0, 64]");
  }
  if (seam_layouts < 1 || seam_layouts > 16) return fail("seam_layouts must be in [1, 16]");
  if (!(outdoor_probability >= 0 && outdoor_probability <= 1))
    return fail("outdoor_probability must be in [0, 1]");
  if (!(seven_segment_share >= 0 && seven_segment_share <= 1))
    return fail("seven_segment_share must be in [0, 1]");
  if (!(coarse_sensor_share >= 0 && coarse_sensor_share <= 1))
    return fail("coarse_sensor_share must be in [0, 1]");
  if (!(nearest_lookup_share >= 0 && nearest_lookup_share <= 1))
    return fail("nearest_lookup_share must be in [0, 1]");
  if (!(ray_seam_share >= 0 && ray_seam_share <= 1))
    return fail("ray_seam_share must be in [0, 1]");
  if (ray_seam_layouts < 0 || ray_seam_layouts > 16)
    return fail("ray_seam_layouts must be in [0, 16]");
  if (!(chroma_noise_share >= 0 && chroma_noise_share <= 1))
    return fail("chroma_noise_share must be in [0, 1]");
  if (!(chroma_noise_max >= 0 && chroma_noise_max <= 50))
    return fail("chroma_noise_max must be in [0, 50] grey levels");
  if (!(parked_car_probability_max >= 0 && parked_car_probability_max <= 1)) {
    return fail("parked_car_probability_max must be in [0, 1]");
  }
  if (!(ego_length_m > 0 && ego_width_m > 0 && ego_rear_overhang_m >= 0)) {
    return fail("ego dimensions must be positive");
  }
  return true;
}

Colour PaintColour(PaintKind paint) {
  switch (paint) {
    case PaintKind::kWhite:
      return {235, 238, 238};
    case PaintKind::kYellow:
      return {40, 185, 225};
    case PaintKind::kRed:
      return {50, 50, 190};
    case PaintKind::kBlue:
      return {170, 100, 40};
    case PaintKind::kBlack:
      return {30, 30, 30};
  }
  return {235, 238, 238};
}

Look SampleLook(std::uint64_t seed, bool outdoor, const SceneSamplerOptions& options) {
  Scene scene;
  scene.seed = seed;
  Random floor_rng = Random::Derive(seed, kFloorTag);
  SampleFloor(floor_rng, outdoor, &scene);
  Random light_rng = Random::Derive(seed, kLightTag);
  SampleLight(light_rng, outdoor, &scene);
  Random cameras = Random::Derive(seed, kCamerasTag);
  SampleCameras(cameras, options, outdoor, &scene);
  return {scene.floor, scene.light, scene.cameras, scene.front_camera};
}

void AddParkedCar(std::uint64_t seed, const Eigen::Vector2d& center, double yaw_rad, Scene* scene) {
  Random rng(seed);
  AddCar(rng, center, yaw_rad, scene);
}

Scene SampleScene(std::uint64_t seed, const SceneSamplerOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument("scene sampler: " + error);
  Scene scene;
  scene.seed = seed;
  Random light_rng = Random::Derive(seed, kLightTag);
  const bool outdoor = light_rng.Bernoulli(options.outdoor_probability);

  Random rows = Random::Derive(seed, kRowsTag);
  // Mostly driving along an aisle with rows on one or both sides; sometimes
  // turning into a slot, the rows at any angle.
  const bool turning = rows.Bernoulli(0.2);
  const double yaw = turning ? rows.Uniform(-kPi / 2, kPi / 2) : rows.Gaussian(0.06);
  const int row_count = turning ? 1 : (rows.Bernoulli(0.55) ? 2 : 1);
  const bool first_left = rows.Bernoulli(0.5);
  const int letter = static_cast<int>(rows.Index(26));
  for (int r = 0; r < row_count; ++r) {
    const bool left = r == 0 ? first_left : !first_left;
    const double offset = turning ? rows.Uniform(-1.0, 3.0) : rows.Uniform(1.2, 4.0);
    const double row_yaw = r == 0 ? yaw : yaw + rows.Gaussian(0.03);
    AddRow(rows, options, left, outdoor, row_yaw, offset, letter + r, &scene);
  }
  Random floor_rng = Random::Derive(seed, kFloorTag);
  SampleFloor(floor_rng, outdoor, &scene);
  Random decals = Random::Derive(seed, kDecalsTag);
  SampleDecals(decals, outdoor, &scene);
  Random text_rng = Random::Derive(seed, kTextTag);
  SampleFloorTexts(text_rng, &scene);
  if (!turning) SampleAisleLines(text_rng, yaw, &scene);
  Random solids = Random::Derive(seed, kSolidsTag);
  SampleMovers(solids, options, &scene);
  SampleLight(light_rng, outdoor, &scene);
  Random cameras = Random::Derive(seed, kCamerasTag);
  SampleCameras(cameras, options, outdoor, &scene);
  return scene;
}

}  // namespace parkslam::scene
