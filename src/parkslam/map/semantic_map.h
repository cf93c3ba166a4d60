#ifndef PARKSLAM_MAP_SEMANTIC_MAP_H_
#define PARKSLAM_MAP_SEMANTIC_MAP_H_

// The 2D semantic map of a parking lot (paper IV-A): slots with their IDs,
// AprilTags, and the obstacles (pillars, walls) the tags are mounted on. The
// simulator's ground truth and the mapper's output share this type and its
// file format (docs/map_format.md).

#include <Eigen/Core>
#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "parkslam/common/lot_constants.h"
#include "parkslam/common/se2.h"
#include "parkslam/sensor/sensor_data.h"

namespace parkslam {

enum class SlotKind { kPerpendicular, kAngled, kParallel };

const char* ToString(SlotKind kind);
std::optional<SlotKind> SlotKindFromString(const std::string& name);

struct MapSlot {
  // The painted ID ("38", "105"); a temporary ID "t<n>" when the mapper could
  // not read it (then `temporary` is true); empty in ground truth for a slot
  // with no painted ID.
  std::string id;
  bool temporary = false;
  // Ground truth only: false when the painted ID is worn beyond reading.
  bool id_legible = true;
  SlotKind kind = SlotKind::kPerpendicular;
  // Corner order as in sensor_data.h: 0-1 is the entrance line.
  std::array<Eigen::Vector2d, kSlotCorners> corners_map{};
  std::array<bool, kSlotCorners> corner_observed{true, true, true, true};
  // Standard deviation of each corner (isotropic), metres; 0 in ground truth.
  std::array<double, kSlotCorners> corner_sigma_m{0.0, 0.0, 0.0, 0.0};
  int observation_count = 0;
  // When a drive last saw it where the map has it: that drive's label
  // (mapping/map_update.h); empty in a map that was never updated.
  std::string last_confirmed;
};

enum class ObstacleKind { kPillar, kWall };

const char* ToString(ObstacleKind kind);
std::optional<ObstacleKind> ObstacleKindFromString(const std::string& name);

// A pillar (closed polygon) or a wall (open polyline of two points).
struct MapObstacle {
  ObstacleKind kind = ObstacleKind::kPillar;
  std::vector<Eigen::Vector2d> points_map;
};

struct MapTag {
  int tag_id = 0;
  Eigen::Vector2d p_map = Eigen::Vector2d::Zero();
  // Direction of the tag's outward normal in the map frame.
  double yaw_map_rad = 0.0;
  double size_m = kDefaultTagSize_m;
  // Index into SemanticMap::obstacles of the pillar or wall it hangs on, or
  // -1 when unknown.
  int obstacle_index = -1;
  // As MapSlot::last_confirmed.
  std::string last_confirmed;
};

struct SemanticMap {
  // Free-form key/value metadata (source, world name, seed, creation time).
  std::map<std::string, std::string> metadata;
  std::vector<MapSlot> slots;
  std::vector<MapTag> tags;
  std::vector<MapObstacle> obstacles;
  // Where the drive that made the map began (its first keyframe), in the
  // map frame: the lot's entrance, for a car that starts its drives there
  // (`localize --init entrance`). Absent in maps made otherwise.
  std::optional<SE2> entrance;
};

}  // namespace parkslam

#endif  // PARKSLAM_MAP_SEMANTIC_MAP_H_
