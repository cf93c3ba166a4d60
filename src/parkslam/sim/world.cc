#include "parkslam/sim/world.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "parkslam/common/angles.h"
#include "parkslam/common/cross.h"
#include "parkslam/common/random.h"
#include "parkslam/sim/world_plan.h"

namespace parkslam::sim {
namespace {

constexpr std::uint64_t kIdStreamTag = 0x1d5;
constexpr std::uint64_t kSlotVariationStreamTag = 0x5107;

Eigen::Vector2d LeftNormal(const Eigen::Vector2d& d) { return Eigen::Vector2d(-d.y(), d.x()); }

std::string PaintedId(int number, int digits) {
  std::string id = std::to_string(number);
  if (static_cast<int>(id.size()) < digits) {
    id.insert(0, static_cast<size_t>(digits) - id.size(), '0');
  }
  return id;
}

// The row as built: with the variation on, a depth, a width and an angle
// error of its own (drawn for every row, so that one row's kind does not
// shift the next row's draws); parallel rows keep their shape.
SlotRowConfig VariedRow(const SlotRowConfig& row, const SlotVariationConfig& variation,
                        Random& rng) {
  const double depth_m = rng.Uniform(variation.depth_min_m, variation.depth_max_m);
  const double width_m = rng.Uniform(variation.width_min_m, variation.width_max_m);
  const double angle_error_deg =
      rng.Uniform(-variation.angle_error_max_deg, variation.angle_error_max_deg);
  if (!variation.enabled || *SlotKindFromString(row.kind) == SlotKind::kParallel) return row;
  SlotRowConfig varied = row;
  varied.depth_m = depth_m;
  varied.width_m = width_m;
  varied.angle_deg = row.angle_deg + angle_error_deg;
  return varied;
}

// Slots of one row and the pillars in the gaps between its groups.
void AddRow(const SlotRowConfig& row, const WorldConfig& config, Random& rng, World* world) {
  const SlotKind kind = *SlotKindFromString(row.kind);
  const double heading = DegToRad(row.direction_deg);
  const Eigen::Vector2d along(std::cos(heading), std::sin(heading));
  const Eigen::Vector2d far =
      row.far_side_left ? LeftNormal(along) : Eigen::Vector2d(-LeftNormal(along));
  const double angle = DegToRad(row.angle_deg);
  const Eigen::Vector2d separating = std::cos(angle) * along + std::sin(angle) * far;
  const double stride_m = row.width_m / std::sin(angle);

  double offset_m = 0.0;
  for (int k = 0; k < row.count; ++k) {
    WorldSlot slot;
    slot.kind = kind;
    const Eigen::Vector2d c0 = row.origin_m + offset_m * along;
    const Eigen::Vector2d c1 = c0 + stride_m * along;
    slot.corners_map = {c0, c1, c1 + row.depth_m * separating, c0 + row.depth_m * separating};
    if (!row.far_side_left) {
      // Canonical order: walking from corner 0 to corner 1, the slot lies on
      // the left (the corners go round counter-clockwise).
      std::swap(slot.corners_map[0], slot.corners_map[1]);
      std::swap(slot.corners_map[2], slot.corners_map[3]);
    }
    // Both draws are always made so that the rates do not shift the stream.
    const bool missing = rng.Bernoulli(config.id_missing_rate);
    const bool worn = rng.Bernoulli(config.id_worn_rate);
    if (!missing) {
      slot.painted_id = PaintedId(row.first_id + k * row.id_step, row.id_digits);
      slot.id_legible = !worn;
    }
    world->slots.push_back(slot);
    offset_m += stride_m;

    const bool end_of_group =
        row.group_size > 0 && (k + 1) % row.group_size == 0 && k + 1 < row.count;
    if (end_of_group) {
      if (row.pillars && row.group_gap_m > 0.0) {
        const double half = config.pillar_size_m / 2;
        const Eigen::Vector2d gap_mid = row.origin_m + (offset_m + row.group_gap_m / 2) * along;
        world->pillars.push_back({gap_mid + row.depth_m * separating - half * far, half});
      }
      offset_m += row.group_gap_m;
    }
  }
}

void AddWall(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
             const Eigen::Vector2d& interior_point, World* world) {
  Eigen::Vector2d normal = LeftNormal((b - a).normalized());
  if (normal.dot(interior_point - a) < 0.0) normal = -normal;
  world->walls.push_back({a, b, normal});
}

void AddWalls(const WorldConfig& c, World* world) {
  const RegionConfig& h = c.hall;
  const Eigen::Vector2d centre((h.min_x_m + h.max_x_m) / 2, (h.min_y_m + h.max_y_m) / 2);
  const Eigen::Vector2d sw(h.min_x_m, h.min_y_m), se(h.max_x_m, h.min_y_m),
      ne(h.max_x_m, h.max_y_m), nw(h.min_x_m, h.max_y_m);
  AddWall(sw, se, centre, world);
  AddWall(se, ne, centre, world);
  AddWall(ne, nw, centre, world);
  if (!c.corridor) {
    AddWall(nw, sw, centre, world);
    return;
  }
  const double y_lo = c.corridor_center_y_m - c.corridor_width_m / 2;
  const double y_hi = c.corridor_center_y_m + c.corridor_width_m / 2;
  AddWall(nw, {h.min_x_m, y_hi}, centre, world);
  AddWall({h.min_x_m, y_lo}, sw, centre, world);
  const double x_out = h.min_x_m - c.corridor_length_m;
  const Eigen::Vector2d corridor_mid(h.min_x_m - c.corridor_length_m / 2, c.corridor_center_y_m);
  AddWall({x_out, y_lo}, {h.min_x_m, y_lo}, corridor_mid, world);
  AddWall({x_out, y_hi}, {h.min_x_m, y_hi}, corridor_mid, world);
}

struct TagPlace {
  Eigen::Vector2d p_map;
  double normal_yaw_rad;
  bool on_pillar;
  int mount_index;
};

std::vector<TagPlace> CandidateTagPlaces(const WorldConfig& c, const World& world) {
  std::vector<TagPlace> places;
  // Walls: corridor walls were added last; visit them first so that the
  // corridor is covered however tag_count thins the candidates.
  std::vector<int> order(world.walls.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return world.walls[a].a_map.x() < world.walls[b].a_map.x();
  });
  for (int w : order) {
    const WorldWall& wall = world.walls[w];
    const double length_m = (wall.b_map - wall.a_map).norm();
    const Eigen::Vector2d dir = (wall.b_map - wall.a_map) / length_m;
    const double yaw = std::atan2(wall.normal_map.y(), wall.normal_map.x());
    // A tag and its white margin (a quarter of the black square each side,
    // plus room for the wall that meets this one) stay within the wall.
    const double keep_m = std::min(c.tag_size_m * 0.75 + 0.1, length_m / 2);
    for (double s = c.tag_spacing_m / 2; s < length_m; s += c.tag_spacing_m) {
      places.push_back(
          {wall.a_map + std::clamp(s, keep_m, length_m - keep_m) * dir, yaw, false, w});
    }
  }
  for (size_t p = 0; p < world.pillars.size(); ++p) {
    const WorldPillar& pillar = world.pillars[p];
    for (int face = 0; face < 4; ++face) {
      const double yaw = face * kPi / 2;
      const Eigen::Vector2d normal(std::cos(yaw), std::sin(yaw));
      places.push_back(
          {pillar.center_map + pillar.half_size_m * normal, yaw, true, static_cast<int>(p)});
    }
  }
  std::vector<TagPlace> inside;
  for (const TagPlace& place : places) {
    for (const RegionConfig& region : c.tag_regions) {
      if (region.Contains(place.p_map)) {
        inside.push_back(place);
        break;
      }
    }
  }
  return inside;
}

void AddTags(const WorldConfig& c, World* world) {
  const std::vector<TagPlace> places = CandidateTagPlaces(c, *world);
  const size_t n = places.size();
  const size_t count = std::min(n, static_cast<size_t>(c.tag_count));
  for (size_t i = 0; i < count; ++i) {
    // Spread evenly over the candidates.
    const size_t k = static_cast<size_t>((static_cast<double>(i) + 0.5) * static_cast<double>(n) /
                                         static_cast<double>(count));
    const TagPlace& place = places[std::min(k, n - 1)];
    world->tags.push_back({static_cast<int>(i), place.p_map, place.normal_yaw_rad, c.tag_size_m,
                           place.on_pillar, place.mount_index});
  }
}

bool SegmentsIntersect(const Eigen::Vector2d& p, const Eigen::Vector2d& p2,
                       const Eigen::Vector2d& q, const Eigen::Vector2d& q2) {
  const Eigen::Vector2d r = p2 - p, s = q2 - q;
  const double denom = Cross(r, s);
  if (std::abs(denom) < 1e-12) return false;  // parallel: treat as clear
  const double t = Cross(q - p, s) / denom;
  const double u = Cross(q - p, r) / denom;
  return t >= 0.0 && t <= 1.0 && u >= 0.0 && u <= 1.0;
}

// Liang-Barsky clip of segment a-b against an axis-aligned square.
bool SegmentHitsSquare(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                       const WorldPillar& pillar) {
  const Eigen::Vector2d lo = pillar.center_map.array() - pillar.half_size_m;
  const Eigen::Vector2d hi = pillar.center_map.array() + pillar.half_size_m;
  const Eigen::Vector2d d = b - a;
  double t0 = 0.0, t1 = 1.0;
  for (int axis = 0; axis < 2; ++axis) {
    if (std::abs(d[axis]) < 1e-12) {
      if (a[axis] < lo[axis] || a[axis] > hi[axis]) return false;
      continue;
    }
    double ta = (lo[axis] - a[axis]) / d[axis];
    double tb = (hi[axis] - a[axis]) / d[axis];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

constexpr std::uint64_t kChangesStreamTag = 0xc4a9;

// The distinct indices [0, n) in an order drawn from rng.
std::vector<std::size_t> Shuffled(std::size_t n, Random& rng) {
  std::vector<std::size_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = i;
  for (std::size_t i = n; i > 1; --i) std::swap(order[i - 1], order[rng.Index(i)]);
  return order;
}

bool TagNear(const World& world, std::size_t skip, const Eigen::Vector2d& p, double radius_m) {
  for (std::size_t i = 0; i < world.tags.size(); ++i) {
    if (i != skip && (world.tags[i].p_map - p).norm() < radius_m) return true;
  }
  return false;
}

// A tag to another place on its mount: along its wall by 3-6 m (either
// way, kept 0.5 m inside the wall), or to the next free face of its pillar.
void MoveTag(std::size_t index, Random& rng, World* world) {
  WorldTag& tag = world->tags[index];
  if (tag.on_pillar) {
    const WorldPillar& pillar = world->pillars[tag.mount_index];
    for (const double turn : {M_PI / 2, -M_PI / 2, M_PI}) {
      const double yaw = NormalizeAngle(tag.normal_yaw_rad + turn);
      const Eigen::Vector2d normal(std::cos(yaw), std::sin(yaw));
      const Eigen::Vector2d p = pillar.center_map + pillar.half_size_m * normal;
      if (TagNear(*world, index, p, 0.3)) continue;
      tag.p_map = p;
      tag.normal_yaw_rad = yaw;
      return;
    }
    return;
  }
  const WorldWall& wall = world->walls[tag.mount_index];
  const double length_m = (wall.b_map - wall.a_map).norm();
  const Eigen::Vector2d along = (wall.b_map - wall.a_map) / length_m;
  const double at_m = (tag.p_map - wall.a_map).dot(along);
  const double step_m = rng.Uniform(3.0, 6.0);
  const double first = rng.Bernoulli(0.5) ? 1.0 : -1.0;
  for (const double sign : {first, -first}) {
    const double to_m = at_m + sign * step_m;
    if (to_m < 0.5 || to_m > length_m - 0.5) continue;
    const Eigen::Vector2d p = tag.p_map + along * (to_m - at_m);
    if (TagNear(*world, index, p, 1.0)) continue;
    tag.p_map = p;
    return;
  }
}

// WorldChangesConfig, laid over the built world.
void ApplyChanges(const WorldChangesConfig& changes, World* world) {
  if (!changes.any()) return;
  Random rng = Random::Derive(static_cast<std::uint64_t>(changes.seed), kChangesStreamTag);
  std::vector<std::size_t> named;
  int highest_id = 0;
  for (std::size_t i = 0; i < world->slots.size(); ++i) {
    const std::string& id = world->slots[i].painted_id;
    if (id.empty()) continue;
    named.push_back(i);
    if (id.find_first_not_of("0123456789") == std::string::npos && id.size() < 9) {
      highest_id = std::max(highest_id, std::stoi(id));
    }
  }
  const std::vector<std::size_t> order = Shuffled(named.size(), rng);
  const auto count = [&](double share) {
    return static_cast<std::size_t>(std::llround(share * static_cast<double>(named.size())));
  };
  const std::size_t moved = std::min(order.size(), count(changes.moved_slot_share));
  const std::size_t repainted = std::min(order.size() - moved, count(changes.repainted_slot_share));
  for (std::size_t k = 0; k < moved; ++k) {
    WorldSlot& slot = world->slots[named[order[k]]];
    // Towards the aisle: against the direction from the entrance to the back.
    const Eigen::Vector2d depth =
        ((slot.corners_map[3] - slot.corners_map[0]) + (slot.corners_map[2] - slot.corners_map[1]))
            .normalized();
    for (Eigen::Vector2d& c : slot.corners_map) c -= changes.moved_slot_shift_m * depth;
  }
  for (std::size_t k = moved; k < moved + repainted; ++k) {
    WorldSlot& slot = world->slots[named[order[k]]];
    slot.painted_id = std::to_string(++highest_id);
    slot.id_legible = true;
  }
  const std::vector<std::size_t> tags = Shuffled(world->tags.size(), rng);
  const std::size_t removed = std::min(tags.size(), static_cast<std::size_t>(changes.removed_tags));
  const std::size_t moved_tags =
      std::min(tags.size() - removed, static_cast<std::size_t>(changes.moved_tags));
  for (std::size_t k = removed; k < removed + moved_tags; ++k) MoveTag(tags[k], rng, world);
  std::vector<std::size_t> gone(tags.begin(), tags.begin() + static_cast<std::ptrdiff_t>(removed));
  std::sort(gone.rbegin(), gone.rend());
  for (const std::size_t i : gone)
    world->tags.erase(world->tags.begin() + static_cast<std::ptrdiff_t>(i));
}

}  // namespace

World BuildWorld(const WorldConfig& config) {
  return BuildWorld(config, static_cast<std::uint64_t>(config.seed));
}

World BuildWorld(const WorldConfig& config, std::uint64_t seed) {
  std::string error;
  if (!config.IsValid(&error)) throw std::invalid_argument(error);
  if (config.plan) {
    World world = BuildWorldFromPlan(*config.plan, config.name, config.hall);
    ApplyChanges(config.changes, &world);
    return world;
  }

  World world;
  world.name = config.name;
  world.hall = config.hall;
  Random rng = Random::Derive(seed, kIdStreamTag);
  // A stream of its own, so that varied rows keep the IDs' draws unchanged.
  Random variation_rng = Random::Derive(seed, kSlotVariationStreamTag);
  for (const SlotRowConfig& row : config.rows) {
    AddRow(VariedRow(row, config.slot_variation, variation_rng), config, rng, &world);
  }
  AddWalls(config, &world);
  AddTags(config, &world);
  world.floor_area_m2 =
      (config.hall.max_x_m - config.hall.min_x_m) * (config.hall.max_y_m - config.hall.min_y_m);
  if (config.corridor) {
    world.floor_area_m2 += config.corridor_length_m * config.corridor_width_m;
  }
  ApplyChanges(config.changes, &world);
  return world;
}

std::vector<RegionConfig> FloorRegions(const WorldConfig& config) {
  if (config.plan) return PlanFloor(*config.plan, config.hall);
  std::vector<RegionConfig> floor{config.hall};
  if (config.corridor) {
    floor.push_back({config.hall.min_x_m - config.corridor_length_m,
                     config.corridor_center_y_m - config.corridor_width_m / 2, config.hall.min_x_m,
                     config.corridor_center_y_m + config.corridor_width_m / 2});
  }
  return floor;
}

SemanticMap ToSemanticMap(const World& world) {
  SemanticMap map;
  map.metadata["source"] = "simulator ground truth";
  map.metadata["world"] = world.name;
  for (const WorldWall& wall : world.walls) {
    map.obstacles.push_back({ObstacleKind::kWall, {wall.a_map, wall.b_map}});
  }
  for (const WorldPillar& pillar : world.pillars) {
    const double h = pillar.half_size_m;
    const Eigen::Vector2d c = pillar.center_map;
    map.obstacles.push_back({ObstacleKind::kPillar,
                             {c + Eigen::Vector2d(-h, -h), c + Eigen::Vector2d(h, -h),
                              c + Eigen::Vector2d(h, h), c + Eigen::Vector2d(-h, h)}});
  }
  for (const WorldSlot& slot : world.slots) {
    MapSlot s;
    s.id = slot.painted_id;
    s.id_legible = slot.id_legible;
    s.kind = slot.kind;
    s.corners_map = slot.corners_map;
    map.slots.push_back(s);
  }
  const int wall_count = static_cast<int>(world.walls.size());
  for (const WorldTag& tag : world.tags) {
    map.tags.push_back({tag.tag_id,
                        tag.p_map,
                        tag.normal_yaw_rad,
                        tag.size_m,
                        tag.on_pillar ? wall_count + tag.mount_index : tag.mount_index,
                        {}});
  }
  return map;
}

bool SegmentBlocked(const World& world, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                    int skip_wall, int skip_pillar) {
  for (size_t i = 0; i < world.walls.size(); ++i) {
    if (static_cast<int>(i) == skip_wall) continue;
    if (SegmentsIntersect(a, b, world.walls[i].a_map, world.walls[i].b_map)) return true;
  }
  for (size_t i = 0; i < world.pillars.size(); ++i) {
    if (static_cast<int>(i) == skip_pillar) continue;
    if (SegmentHitsSquare(a, b, world.pillars[i])) return true;
  }
  return false;
}

}  // namespace parkslam::sim
