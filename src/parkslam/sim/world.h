#ifndef PARKSLAM_SIM_WORLD_H_
#define PARKSLAM_SIM_WORLD_H_

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "parkslam/common/lot_constants.h"
#include "parkslam/map/semantic_map.h"
#include "parkslam/sim/scenario_config.h"

namespace parkslam::sim {

struct WorldSlot {
  SlotKind kind = SlotKind::kPerpendicular;
  std::array<Eigen::Vector2d, kSlotCorners> corners_map{};
  std::string painted_id;  // empty: no ID painted
  bool id_legible = true;  // false: painted but worn beyond reading
};

// A wall segment. It blocks sight from both sides; tags hang on the side
// its unit normal_map points to (into the hall or the corridor).
struct WorldWall {
  Eigen::Vector2d a_map, b_map;
  Eigen::Vector2d normal_map;
};

// An axis-aligned square pillar.
struct WorldPillar {
  Eigen::Vector2d center_map;
  double half_size_m = 0.3;
};

struct WorldTag {
  int tag_id = 0;
  Eigen::Vector2d p_map;        // centre of the tag
  double normal_yaw_rad = 0.0;  // outward normal, map frame
  double size_m = kDefaultTagSize_m;
  bool on_pillar = false;
  int mount_index = 0;  // index into pillars or walls
};

struct World {
  std::string name;
  RegionConfig hall;
  std::vector<WorldSlot> slots;
  std::vector<WorldWall> walls;
  std::vector<WorldPillar> pillars;
  std::vector<WorldTag> tags;

  // Total floor area of hall and corridor, square metres.
  double floor_area_m2 = 0.0;
};

// Builds the world from its configuration. Deterministic: the seed decides
// which IDs are missing or worn and which candidate places carry tags. With
// config.plan, the world is the plan's (BuildWorldFromPlan) and the seed
// plays no part. Throws std::invalid_argument when the configuration is
// invalid.
World BuildWorld(const WorldConfig& config, std::uint64_t seed);
// The same with the configuration's own seed (config.seed): the lot a
// scenario names.
World BuildWorld(const WorldConfig& config);

// The drivable floor as rectangles: a plan's floor, else the hall and the
// corridor.
std::vector<RegionConfig> FloorRegions(const WorldConfig& config);

// The ground truth as a map in the project's map format: slots (IDs, all
// four corners observed, zero uncertainty), tags, and obstacles (pillars as
// squares, walls as segments), tag obstacle indices pointing at them.
SemanticMap ToSemanticMap(const World& world);

// True when the segment a-b crosses a wall (other than skip_wall) or a pillar
// (other than skip_pillar). Used for line-of-sight tests.
bool SegmentBlocked(const World& world, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                    int skip_wall, int skip_pillar);

}  // namespace parkslam::sim

#endif  // PARKSLAM_SIM_WORLD_H_
