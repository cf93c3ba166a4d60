#include "parkslam/map/semantic_map.h"

namespace parkslam {

const char* ToString(SlotKind kind) {
  switch (kind) {
    case SlotKind::kPerpendicular:
      return "perpendicular";
    case SlotKind::kAngled:
      return "angled";
    case SlotKind::kParallel:
      return "parallel";
  }
  return "perpendicular";
}

std::optional<SlotKind> SlotKindFromString(const std::string& name) {
  if (name == "perpendicular") return SlotKind::kPerpendicular;
  if (name == "angled") return SlotKind::kAngled;
  if (name == "parallel") return SlotKind::kParallel;
  return std::nullopt;
}

const char* ToString(ObstacleKind kind) { return kind == ObstacleKind::kWall ? "wall" : "pillar"; }

std::optional<ObstacleKind> ObstacleKindFromString(const std::string& name) {
  if (name == "pillar") return ObstacleKind::kPillar;
  if (name == "wall") return ObstacleKind::kWall;
  return std::nullopt;
}

}  // namespace parkslam
