#ifndef PARKSLAM_SIM_WORLD_PLAN_H_
#define PARKSLAM_SIM_WORLD_PLAN_H_

// A world given explicitly, as from a real garage's plan or a map: every
// slot with its four corners and painted ID, every wall, pillar and tag,
// instead of rows generated from a few numbers. WorldConfig::plan holds one;
// BuildWorld() then takes the lot from it as it stands (docs/world_plan.md).
// Coordinates are in the map frame, metres.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "parkslam/common/lot_constants.h"
#include "parkslam/map/semantic_map.h"
#include "parkslam/sim/region.h"

namespace parkslam::sim {

struct World;

// One slot. Corners 0-1 are the entrance line; the four go round
// counter-clockwise (the slot lies left of the walk from corner 0 to 1).
struct PlanSlot {
  std::string kind = "perpendicular";  // perpendicular | angled | parallel
  std::vector<Eigen::Vector2d> corners_m;
  std::string painted_id;  // empty: no ID painted
  bool id_legible = true;  // false: painted but worn beyond reading

  template <typename V>
  void VisitFields(V& v) {
    v("kind", kind);
    v("corners_m", corners_m);
    v("painted_id", painted_id);
    v("id_legible", id_legible);
  }
};

// A wall segment from a_m to b_m; tags hang on the side its unit normal
// points to.
struct PlanWall {
  Eigen::Vector2d a_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d b_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d normal = Eigen::Vector2d::Zero();

  template <typename V>
  void VisitFields(V& v) {
    v("a_m", a_m);
    v("b_m", b_m);
    v("normal", normal);
  }
};

// An axis-aligned square pillar.
struct PlanPillar {
  Eigen::Vector2d center_m = Eigen::Vector2d::Zero();
  double half_size_m = 0.3;

  template <typename V>
  void VisitFields(V& v) {
    v("center_m", center_m);
    v("half_size_m", half_size_m);
  }
};

// An AprilTag (tag36h11). mount names what it hangs on (that wall or pillar
// does not hide it): wall or pillar with mount_index into walls or pillars,
// or none.
struct PlanTag {
  int id = 0;
  Eigen::Vector2d p_m = Eigen::Vector2d::Zero();  // centre of the tag
  double normal_yaw_deg = 0.0;                    // outward normal, map frame
  double size_m = kDefaultTagSize_m;
  std::string mount = "none";  // wall | pillar | none
  int mount_index = -1;

  template <typename V>
  void VisitFields(V& v) {
    v("id", id);
    v("p_m", p_m);
    v("normal_yaw_deg", normal_yaw_deg);
    v("size_m", size_m);
    v("mount", mount);
    v("mount_index", mount_index);
  }
};

// The drivable floor as axis-aligned rectangles (hall, corridors): the
// route must stay on it, and its area is the sum of theirs (they must not
// overlap). Empty: the world's hall alone.
struct WorldPlan {
  std::vector<RegionConfig> floor;
  std::vector<PlanSlot> slots;
  std::vector<PlanWall> walls;
  std::vector<PlanPillar> pillars;
  std::vector<PlanTag> tags;

  template <typename V>
  void VisitFields(V& v) {
    v("floor", floor);
    v("slots", slots);
    v("walls", walls);
    v("pillars", pillars);
    v("tags", tags);
  }
};

// Checks the plan: a slot has four distinct corners going round
// counter-clockwise with sides within the plausible slot sizes and corner
// angles near a parallelogram's; painted IDs and tag IDs unique; walls of
// non-zero length with a unit normal; tags mounted on an existing wall or
// pillar of that kind. `hall` is the world's hall, the floor when
// plan.floor is empty. On failure names the field under `prefix`
// ("world.plan.slots[3].corners_m: ...") in *error.
bool IsValidPlan(const WorldPlan& plan, const RegionConfig& hall, const std::string& prefix,
                 std::string* error);

// The floor rectangles of a plan: plan.floor, or the hall alone.
std::vector<RegionConfig> PlanFloor(const WorldPlan& plan, const RegionConfig& hall);

// Checks that a route's waypoints lie on the floor and that no straight leg
// between two of them leaves it or runs through a wall or pillar of the
// world; names the waypoints under `field` in *error.
bool IsDrivableRoute(const std::vector<Eigen::Vector2d>& waypoints_m,
                     const std::vector<RegionConfig>& floor, const World& world,
                     const std::string& field, std::string* error);

// The world of a plan, its slots, walls, pillars and tags in the plan's
// order. Throws std::invalid_argument when IsValidPlan fails.
World BuildWorldFromPlan(const WorldPlan& plan, const std::string& name, const RegionConfig& hall);

// The plan of a built world: BuildWorldFromPlan(PlanFromWorld(w, f), ...)
// gives w's slots, walls, pillars and tags again.
WorldPlan PlanFromWorld(const World& world, const std::vector<RegionConfig>& floor);

// The plan of a map (a ground truth, or a map built by the mapper): its
// slots (temporary IDs become unpainted slots), tags, pillars (the
// axis-aligned square of each pillar polygon's bounding box, half its
// longer side) and walls (each leg of a wall polyline; its normal points to
// the side its tags face, else towards the centroid of the slots). Tags
// keep their obstacle as mount; the floor is left empty.
WorldPlan PlanFromMap(const SemanticMap& map);

// The bounding box of a map's obstacles and slots, grown by margin_m: a hall
// for the plan of a map.
RegionConfig MapBounds(const SemanticMap& map, double margin_m);

}  // namespace parkslam::sim

#endif  // PARKSLAM_SIM_WORLD_PLAN_H_
