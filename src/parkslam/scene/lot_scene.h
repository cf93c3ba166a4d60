#ifndef PARKSLAM_SCENE_LOT_SCENE_H_
#define PARKSLAM_SCENE_LOT_SCENE_H_

// A whole lot as one scene (scene.h) in the map frame, for drives through
// the scene renderer: the world's slots painted as one lot family paints
// them (line width, entrance stubs or a continuous entrance line, a back
// line or none), their IDs in a real font at one of the family's places,
// the walls and pillars as solids with their AprilTags (paper III-B),
// parked cars in a share of the slots, dirt, and a look (floor, light,
// cameras) named by a preset or drawn from a seed. The static world is
// built once; LotRenderer (lot_renderer.h) shows it from the car.

#include <cstdint>
#include <string>
#include <vector>

#include "parkslam/scene/scene.h"
#include "parkslam/sim/world.h"

namespace parkslam::scene {

struct LotLook {
  // A preset (LotPresetNames()) or "seed": everything drawn from `seed`.
  std::string preset = "epoxy";
  std::uint64_t seed = 1;
  // Share of the slots with a parked car; -1: drawn from
  // [0.3, 0.7] by the seed.
  double parked_share = -1.0;

  bool IsValid(std::string* error) const;
};

// The named looks: bright indoor epoxy, dim worn concrete, an underground
// deck with lamp glare and puddles, outdoor asphalt with sun and hard
// shadows, yellow paint, faded paint with repaints.
const std::vector<std::string>& LotPresetNames();

// The lot of `world` with `look`, in the map frame. Deterministic by the
// look. Throws std::invalid_argument for an invalid look.
Scene BuildLotScene(const sim::World& world, const LotLook& look);

}  // namespace parkslam::scene

#endif  // PARKSLAM_SCENE_LOT_SCENE_H_
