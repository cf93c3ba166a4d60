#include "parkslam/sim/world_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <stdexcept>

#include "parkslam/common/angles.h"
#include "parkslam/common/cross.h"
#include "parkslam/common/field_checker.h"
#include "parkslam/common/plausible_ranges.h"
#include "parkslam/sim/world.h"

namespace parkslam::sim {
namespace {

// A slot's corners may miss a parallelogram by this much (the distance
// between the midpoints of its diagonals): painted lines are not exact.
constexpr double kMaxParallelogramError_m = 0.3;
// A tag hangs at most this far from the face of the wall or pillar it is
// mounted on.
constexpr double kMaxTagMountDistance_m = 0.1;
// A wall's normal: unit length and perpendicular to the wall within this.
constexpr double kNormalTolerance = 1e-3;
constexpr double kMinWallLength_m = 0.1;
// The tag36h11 family.
constexpr int kTagFamilySize = 587;
constexpr int kMaxIdDigits = 4;
// Legs of a route are checked for staying on the floor at this spacing.
constexpr double kFloorCheckStep_m = 0.25;

std::string Number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", value);
  return buffer;
}

std::string Index(const std::string& field, size_t i) {
  return field + "[" + std::to_string(i) + "]";
}

// A plan's point: finite and within the coordinate range.
void RequirePoint(FieldChecker& c, const Eigen::Vector2d& p, const std::string& field) {
  c.Require(
      p.allFinite() && std::abs(p.x()) <= kMaxCoordinate_m && std::abs(p.y()) <= kMaxCoordinate_m,
      field, "must be finite and at most " + Number(kMaxCoordinate_m) + " m in magnitude");
}

std::string Join(const std::string& prefix, const std::string& key) {
  return prefix.empty() ? key : prefix + "." + key;
}

void CheckSlot(const PlanSlot& slot, const std::string& field, FieldChecker& c) {
  c.Require(SlotKindFromString(slot.kind).has_value(), field + ".kind",
            "must be perpendicular, angled or parallel");
  const std::string corners = field + ".corners_m";
  c.Require(slot.corners_m.size() == kSlotCorners, corners,
            "needs four corners, got " + std::to_string(slot.corners_m.size()));
  if (!c.ok()) return;
  for (size_t k = 0; k < kSlotCorners; ++k) RequirePoint(c, slot.corners_m[k], Index(corners, k));
  const auto& p = slot.corners_m;
  for (size_t k = 0; k < kSlotCorners && c.ok(); ++k) {
    const double side_m = (p[(k + 1) % kSlotCorners] - p[k]).norm();
    c.Require(side_m >= kMinSlotSide_m && side_m <= kMaxSlotSide_m, corners,
              "side " + std::to_string(k) + "-" + std::to_string((k + 1) % kSlotCorners) + " is " +
                  Number(side_m) + " m long, not in [" + Number(kMinSlotSide_m) + ", " +
                  Number(kMaxSlotSide_m) + "] m");
  }
  // Every corner turns left: a convex quadrilateral, counter-clockwise.
  for (size_t k = 0; k < kSlotCorners && c.ok(); ++k) {
    const Eigen::Vector2d in = p[k] - p[(k + 3) % kSlotCorners];
    const Eigen::Vector2d out = p[(k + 1) % kSlotCorners] - p[k];
    c.Require(Cross(in, out) > 0.0, corners,
              "corner " + std::to_string(k) +
                  " does not turn left: the corners must go round counter-clockwise, 0-1 the "
                  "entrance line, the slot on its left");
  }
  if (!c.ok()) return;
  const double error_m = ((p[0] + p[2]) / 2 - (p[1] + p[3]) / 2).norm();
  c.Require(error_m <= kMaxParallelogramError_m, corners,
            "not a parallelogram: the midpoints of its diagonals are " + Number(error_m) +
                " m apart (at most " + Number(kMaxParallelogramError_m) + " m)");
  const Eigen::Vector2d entrance = p[1] - p[0], side = p[3] - p[0];
  const double angle_deg =
      RadToDeg(std::atan2(Cross(entrance, side), entrance.dot(side)));  // in (0, 180)
  c.Require(angle_deg >= kMinSlotAngle_deg && angle_deg <= kMaxSlotAngle_deg, corners,
            "the side 0-3 meets the entrance line at " + Number(angle_deg) + " deg, not in [" +
                Number(kMinSlotAngle_deg) + ", " + Number(kMaxSlotAngle_deg) + "]");
  const std::string id = field + ".painted_id";
  c.Require(slot.painted_id.size() <= kMaxIdDigits &&
                std::all_of(slot.painted_id.begin(), slot.painted_id.end(),
                            [](char ch) { return ch >= '0' && ch <= '9'; }),
            id, "must be empty or 1 to 4 digits");
}

// Distance from p to the boundary of a pillar's square.
double DistanceToSquare(const Eigen::Vector2d& p, const PlanPillar& pillar) {
  const Eigen::Vector2d d = (p - pillar.center_m).cwiseAbs();
  const Eigen::Vector2d outside = (d.array() - pillar.half_size_m).max(0.0);
  if (outside.squaredNorm() > 0.0) return outside.norm();
  return pillar.half_size_m - d.maxCoeff();
}

double DistanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                         const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

void CheckTag(const PlanTag& tag, const WorldPlan& plan, const std::string& field,
              FieldChecker& c) {
  c.Require(tag.id >= 0 && tag.id < kTagFamilySize, field + ".id",
            "must be in [0, " + std::to_string(kTagFamilySize - 1) + "] (the tag36h11 family)");
  RequirePoint(c, tag.p_m, field + ".p_m");
  c.Require(std::isfinite(tag.normal_yaw_deg) && std::abs(tag.normal_yaw_deg) <= kMaxAngle_deg,
            field + ".normal_yaw_deg", "must be at most " + Number(kMaxAngle_deg) + " deg");
  c.Require(tag.size_m > 0.0 && tag.size_m <= kMaxTagSize_m, field + ".size_m",
            "must be in (0, " + Number(kMaxTagSize_m) + "] m");
  const std::string mount = field + ".mount_index";
  if (tag.mount == "none") {
    c.Require(tag.mount_index == -1, mount, "must be -1 when mount is none");
  } else if (tag.mount == "wall") {
    c.Require(tag.mount_index >= 0 && tag.mount_index < static_cast<int>(plan.walls.size()), mount,
              "names no wall (the plan has " + std::to_string(plan.walls.size()) + ")");
    if (!c.ok()) return;
    const PlanWall& wall = plan.walls[static_cast<size_t>(tag.mount_index)];
    const double distance_m = DistanceToSegment(tag.p_m, wall.a_m, wall.b_m);
    c.Require(distance_m <= kMaxTagMountDistance_m, field + ".p_m",
              "lies " + Number(distance_m) + " m from its wall " + std::to_string(tag.mount_index));
  } else if (tag.mount == "pillar") {
    c.Require(tag.mount_index >= 0 && tag.mount_index < static_cast<int>(plan.pillars.size()),
              mount, "names no pillar (the plan has " + std::to_string(plan.pillars.size()) + ")");
    if (!c.ok()) return;
    const double distance_m =
        DistanceToSquare(tag.p_m, plan.pillars[static_cast<size_t>(tag.mount_index)]);
    c.Require(distance_m <= kMaxTagMountDistance_m, field + ".p_m",
              "lies " + Number(distance_m) + " m from the face of its pillar " +
                  std::to_string(tag.mount_index));
  } else {
    c.Require(false, field + ".mount", "must be wall, pillar or none");
  }
}

void CheckRegion(const RegionConfig& r, const std::string& field, FieldChecker& c) {
  RequirePoint(c, {r.min_x_m, r.min_y_m}, field);
  RequirePoint(c, {r.max_x_m, r.max_y_m}, field);
  c.Require(r.max_x_m > r.min_x_m && r.max_y_m > r.min_y_m, field,
            "max_x_m and max_y_m must exceed min_x_m and min_y_m");
}

bool OnFloor(const Eigen::Vector2d& p, const std::vector<RegionConfig>& floor) {
  return std::any_of(floor.begin(), floor.end(),
                     [&](const RegionConfig& r) { return r.Contains(p); });
}

Eigen::Vector2d LeftNormal(const Eigen::Vector2d& d) { return Eigen::Vector2d(-d.y(), d.x()); }

}  // namespace

bool IsValidPlan(const WorldPlan& plan, const RegionConfig& hall, const std::string& prefix,
                 std::string* error) {
  FieldChecker c(error);
  for (size_t i = 0; i < plan.floor.size(); ++i) {
    CheckRegion(plan.floor[i], Index(Join(prefix, "floor"), i), c);
  }
  CheckRegion(hall, Join(prefix, "hall"), c);
  std::set<std::string> painted;
  for (size_t i = 0; i < plan.slots.size() && c.ok(); ++i) {
    const std::string field = Index(Join(prefix, "slots"), i);
    CheckSlot(plan.slots[i], field, c);
    const std::string& id = plan.slots[i].painted_id;
    c.Require(id.empty() || painted.insert(id).second, field + ".painted_id",
              "'" + id + "' is painted on another slot too");
  }
  for (size_t i = 0; i < plan.walls.size() && c.ok(); ++i) {
    const PlanWall& wall = plan.walls[i];
    const std::string field = Index(Join(prefix, "walls"), i);
    RequirePoint(c, wall.a_m, field + ".a_m");
    RequirePoint(c, wall.b_m, field + ".b_m");
    const double length_m = (wall.b_m - wall.a_m).norm();
    c.Require(length_m >= kMinWallLength_m, field + ".b_m",
              "the wall is " + Number(length_m) + " m long (at least " + Number(kMinWallLength_m) +
                  " m)");
    if (!c.ok()) break;
    c.Require(wall.normal.allFinite() && std::abs(wall.normal.norm() - 1.0) <= kNormalTolerance &&
                  std::abs(wall.normal.dot(wall.b_m - wall.a_m) / length_m) <= kNormalTolerance,
              field + ".normal", "must be a unit vector perpendicular to the wall");
  }
  for (size_t i = 0; i < plan.pillars.size() && c.ok(); ++i) {
    const PlanPillar& pillar = plan.pillars[i];
    const std::string field = Index(Join(prefix, "pillars"), i);
    RequirePoint(c, pillar.center_m, field + ".center_m");
    c.Require(pillar.half_size_m > 0.0 && pillar.half_size_m <= kMaxSlotSide_m,
              field + ".half_size_m", "must be in (0, " + Number(kMaxSlotSide_m) + "] m");
  }
  std::set<int> tag_ids;
  for (size_t i = 0; i < plan.tags.size() && c.ok(); ++i) {
    const std::string field = Index(Join(prefix, "tags"), i);
    CheckTag(plan.tags[i], plan, field, c);
    c.Require(tag_ids.insert(plan.tags[i].id).second, field + ".id",
              std::to_string(plan.tags[i].id) + " is the ID of another tag too");
  }
  return c.ok();
}

std::vector<RegionConfig> PlanFloor(const WorldPlan& plan, const RegionConfig& hall) {
  return plan.floor.empty() ? std::vector<RegionConfig>{hall} : plan.floor;
}

bool IsDrivableRoute(const std::vector<Eigen::Vector2d>& waypoints_m,
                     const std::vector<RegionConfig>& floor, const World& world,
                     const std::string& field, std::string* error) {
  FieldChecker c(error);
  for (size_t i = 0; i < waypoints_m.size() && c.ok(); ++i) {
    const Eigen::Vector2d& p = waypoints_m[i];
    // Built in steps: GCC 12 warns wrongly on "literal" + std::string (its
    // bug 105329).
    std::string where = "(";
    where += Number(p.x()) + ", " + Number(p.y()) + ") is off the floor";
    c.Require(OnFloor(p, floor), Index(field, i), where);
  }
  for (size_t i = 0; i + 1 < waypoints_m.size() && c.ok(); ++i) {
    const Eigen::Vector2d a = waypoints_m[i], b = waypoints_m[i + 1];
    const std::string leg = Index(field, i) + " to [" + std::to_string(i + 1) + "]";
    const int steps = static_cast<int>(std::ceil((b - a).norm() / kFloorCheckStep_m));
    for (int k = 1; k < steps && c.ok(); ++k) {
      c.Require(OnFloor(a + (b - a) * (static_cast<double>(k) / steps), floor), leg,
                "the leg leaves the floor");
    }
    c.Require(!SegmentBlocked(world, a, b, -1, -1), leg, "the leg runs through a wall or pillar");
  }
  return c.ok();
}

World BuildWorldFromPlan(const WorldPlan& plan, const std::string& name, const RegionConfig& hall) {
  std::string error;
  if (!IsValidPlan(plan, hall, "world.plan", &error)) throw std::invalid_argument(error);
  World world;
  world.name = name;
  world.hall = hall;
  for (const PlanSlot& s : plan.slots) {
    WorldSlot slot;
    slot.kind = *SlotKindFromString(s.kind);
    std::copy(s.corners_m.begin(), s.corners_m.end(), slot.corners_map.begin());
    slot.painted_id = s.painted_id;
    slot.id_legible = s.id_legible;
    world.slots.push_back(slot);
  }
  for (const PlanWall& w : plan.walls) world.walls.push_back({w.a_m, w.b_m, w.normal});
  for (const PlanPillar& p : plan.pillars) world.pillars.push_back({p.center_m, p.half_size_m});
  for (const PlanTag& t : plan.tags) {
    world.tags.push_back(
        {t.id, t.p_m, DegToRad(t.normal_yaw_deg), t.size_m, t.mount == "pillar", t.mount_index});
  }
  for (const RegionConfig& r : PlanFloor(plan, hall)) {
    world.floor_area_m2 += (r.max_x_m - r.min_x_m) * (r.max_y_m - r.min_y_m);
  }
  return world;
}

WorldPlan PlanFromWorld(const World& world, const std::vector<RegionConfig>& floor) {
  WorldPlan plan;
  plan.floor = floor;
  for (const WorldSlot& s : world.slots) {
    plan.slots.push_back({ToString(s.kind),
                          {s.corners_map.begin(), s.corners_map.end()},
                          s.painted_id,
                          s.id_legible});
  }
  for (const WorldWall& w : world.walls) plan.walls.push_back({w.a_map, w.b_map, w.normal_map});
  for (const WorldPillar& p : world.pillars) plan.pillars.push_back({p.center_map, p.half_size_m});
  for (const WorldTag& t : world.tags) {
    const char* mount = t.on_pillar ? "pillar" : (t.mount_index >= 0 ? "wall" : "none");
    plan.tags.push_back({t.tag_id, t.p_map, RadToDeg(t.normal_yaw_rad), t.size_m, mount,
                         t.mount_index >= 0 ? t.mount_index : -1});
  }
  return plan;
}

WorldPlan PlanFromMap(const SemanticMap& map) {
  WorldPlan plan;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const MapSlot& s : map.slots) {
    plan.slots.push_back({ToString(s.kind),
                          {s.corners_map.begin(), s.corners_map.end()},
                          s.temporary ? std::string() : s.id,
                          s.id_legible});
    for (const Eigen::Vector2d& p : s.corners_map) {
      centroid += p / (4.0 * static_cast<double>(map.slots.size()));
    }
  }
  if (map.slots.empty()) {
    const RegionConfig bounds = MapBounds(map, 0.0);
    centroid =
        Eigen::Vector2d(bounds.min_x_m + bounds.max_x_m, bounds.min_y_m + bounds.max_y_m) / 2;
  }

  // Obstacles: where each one went (its first wall leg, or its pillar).
  struct Placed {
    bool pillar = false;
    int first = -1, count = 0;
  };
  std::vector<Placed> placed(map.obstacles.size());
  for (size_t i = 0; i < map.obstacles.size(); ++i) {
    const MapObstacle& o = map.obstacles[i];
    if (o.points_map.empty()) continue;
    if (o.kind == ObstacleKind::kPillar) {
      Eigen::Vector2d lo = o.points_map.front(), hi = lo;
      for (const Eigen::Vector2d& p : o.points_map) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
      placed[i] = {true, static_cast<int>(plan.pillars.size()), 1};
      plan.pillars.push_back({(lo + hi) / 2, (hi - lo).maxCoeff() / 2});
      continue;
    }
    placed[i] = {false, static_cast<int>(plan.walls.size()), 0};
    for (size_t k = 0; k + 1 < o.points_map.size(); ++k) {
      const Eigen::Vector2d a = o.points_map[k], b = o.points_map[k + 1];
      if ((b - a).norm() < kMinWallLength_m) continue;
      Eigen::Vector2d normal = LeftNormal((b - a).normalized());
      if (normal.dot(centroid - a) < 0.0) normal = -normal;
      plan.walls.push_back({a, b, normal});
      ++placed[i].count;
    }
  }
  for (const MapTag& t : map.tags) {
    PlanTag tag{t.tag_id, t.p_map, RadToDeg(t.yaw_map_rad), t.size_m, "none", -1};
    const int o = t.obstacle_index;
    if (o >= 0 && o < static_cast<int>(placed.size()) && placed[o].count > 0) {
      if (placed[o].pillar) {
        tag.mount = "pillar";
        tag.mount_index = placed[o].first;
      } else {
        // The nearest leg of the wall; its normal turns to the tag's face.
        double best = std::numeric_limits<double>::infinity();
        for (int k = placed[o].first; k < placed[o].first + placed[o].count; ++k) {
          const PlanWall& w = plan.walls[static_cast<size_t>(k)];
          const double d = DistanceToSegment(t.p_map, w.a_m, w.b_m);
          if (d < best) {
            best = d;
            tag.mount_index = k;
          }
        }
        tag.mount = "wall";
        PlanWall& wall = plan.walls[static_cast<size_t>(tag.mount_index)];
        const Eigen::Vector2d facing(std::cos(t.yaw_map_rad), std::sin(t.yaw_map_rad));
        if (wall.normal.dot(facing) < 0.0) wall.normal = -wall.normal;
      }
    }
    plan.tags.push_back(tag);
  }
  return plan;
}

RegionConfig MapBounds(const SemanticMap& map, double margin_m) {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  auto add = [&](const Eigen::Vector2d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  };
  for (const MapObstacle& o : map.obstacles) {
    for (const Eigen::Vector2d& p : o.points_map) add(p);
  }
  for (const MapSlot& s : map.slots) {
    for (const Eigen::Vector2d& p : s.corners_map) add(p);
  }
  for (const MapTag& t : map.tags) add(t.p_map);
  if (!lo.allFinite()) return {};
  return {lo.x() - margin_m, lo.y() - margin_m, hi.x() + margin_m, hi.y() + margin_m};
}

}  // namespace parkslam::sim
