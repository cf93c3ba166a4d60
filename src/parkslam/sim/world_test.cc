#include "parkslam/sim/world.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "parkslam/common/angles.h"

namespace parkslam::sim {
namespace {

double SignedArea(const std::array<Eigen::Vector2d, 4>& c) {
  double a = 0.0;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d& p = c[i];
    const Eigen::Vector2d& q = c[(i + 1) % 4];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return a / 2;
}

TEST(DefaultWorldTest, MeetsThePaperLotSize) {
  const World world = BuildWorld(DefaultScenario().world, 1);
  EXPECT_GE(world.floor_area_m2, 3000.0);
  EXPECT_GE(world.slots.size(), 100u);
  EXPECT_GE(world.tags.size(), 55u);
  EXPECT_LE(world.tags.size(), 65u);
  EXPECT_FALSE(world.pillars.empty());
}

TEST(DefaultWorldTest, HasAllThreeSlotKindsAndThreeDigitIds) {
  const World world = BuildWorld(DefaultScenario().world, 1);
  std::set<SlotKind> kinds;
  bool three_digit = false;
  for (const WorldSlot& s : world.slots) {
    kinds.insert(s.kind);
    three_digit |= s.painted_id.size() == 3;
  }
  EXPECT_EQ(kinds.size(), 3u);
  EXPECT_TRUE(three_digit);
}

TEST(DefaultWorldTest, SlotsAreCounterClockwiseWithEntranceFirst) {
  const World world = BuildWorld(DefaultScenario().world, 1);
  for (const WorldSlot& s : world.slots) {
    EXPECT_GT(SignedArea(s.corners_map), 0.0);
    const double entrance = (s.corners_map[1] - s.corners_map[0]).norm();
    const double side = (s.corners_map[3] - s.corners_map[0]).norm();
    if (s.kind == SlotKind::kParallel) {
      EXPECT_NEAR(entrance, 6.0, 1e-9);
      EXPECT_NEAR(side, 2.5, 1e-9);
    } else {
      EXPECT_NEAR(side, 5.3, 1e-9);
    }
  }
}

// Rows of the default lot with the variation on: each non-parallel row has
// one depth, one width and one angle of its own, inside the ranges; rows
// differ; the painted IDs are those of the lot without variation.
TEST(DefaultWorldTest, VariedRowsDrawTheirOwnDepthWidthAndAngle) {
  WorldConfig config = DefaultScenario().world;
  const World plain = BuildWorld(config, 1);
  config.slot_variation.enabled = true;
  const World varied = BuildWorld(config, 1);
  ASSERT_EQ(varied.slots.size(), plain.slots.size());
  const SlotVariationConfig& v = config.slot_variation;
  std::set<long> depths_mm;
  size_t first = 0;
  for (const SlotRowConfig& row : config.rows) {
    const WorldSlot& s0 = varied.slots[first];
    const Eigen::Vector2d entrance0 = s0.corners_map[1] - s0.corners_map[0];
    const Eigen::Vector2d side0 = s0.corners_map[3] - s0.corners_map[0];
    for (int k = 0; k < row.count; ++k) {
      const WorldSlot& s = varied.slots[first + static_cast<size_t>(k)];
      EXPECT_EQ(s.painted_id, plain.slots[first + static_cast<size_t>(k)].painted_id);
      const Eigen::Vector2d side = s.corners_map[3] - s.corners_map[0];
      const Eigen::Vector2d entrance = s.corners_map[1] - s.corners_map[0];
      EXPECT_NEAR(side.norm(), side0.norm(), 1e-9) << s.painted_id;
      EXPECT_NEAR(entrance.norm(), entrance0.norm(), 1e-9) << s.painted_id;
      if (s.kind == SlotKind::kParallel) {
        EXPECT_NEAR(side.norm(), 2.5, 1e-9);
        continue;
      }
      EXPECT_GE(side.norm(), v.depth_min_m);
      EXPECT_LE(side.norm(), v.depth_max_m);
      const double angle_deg =
          std::acos(std::abs(entrance.normalized().dot(side.normalized()))) * 180.0 / kPi;
      EXPECT_NEAR(angle_deg, 90.0 - std::abs(90.0 - row.angle_deg), v.angle_error_max_deg + 1e-9)
          << s.painted_id;
      // The width is measured across the separating lines.
      const double width_m = entrance.norm() * std::sin(angle_deg * kPi / 180.0);
      EXPECT_GE(width_m, v.width_min_m - 1e-9);
      EXPECT_LE(width_m, v.width_max_m + 1e-9);
    }
    if (s0.kind != SlotKind::kParallel) depths_mm.insert(std::lround(side0.norm() * 1000));
    first += static_cast<size_t>(row.count);
  }
  EXPECT_GE(depths_mm.size(), 5u) << "rows should not share one depth";
}

TEST(DefaultWorldTest, EastPartHasNoTag) {
  const World world = BuildWorld(DefaultScenario().world, 1);
  int corridor_tags = 0;
  for (const WorldTag& t : world.tags) {
    EXPECT_LE(t.p_map.x(), 30.0);
    corridor_tags += t.p_map.x() < 0.0;
  }
  EXPECT_GE(corridor_tags, 15);
}

// A tag with its white margin lies within its wall, clear of the wall that
// meets it at an end (tag 39 of the default lot once sat 0.1 m from one).
TEST(DefaultWorldTest, WallTagsLieWithinTheirWalls) {
  const World world = BuildWorld(DefaultScenario().world, 1);
  int on_walls = 0;
  for (const WorldTag& tag : world.tags) {
    if (tag.on_pillar) continue;
    const WorldWall& wall = world.walls[static_cast<size_t>(tag.mount_index)];
    const double length = (wall.b_map - wall.a_map).norm();
    const double s = (tag.p_map - wall.a_map).dot((wall.b_map - wall.a_map) / length);
    EXPECT_GE(s, 0.75 * tag.size_m) << "tag " << tag.tag_id;
    EXPECT_LE(s, length - 0.75 * tag.size_m) << "tag " << tag.tag_id;
    ++on_walls;
  }
  EXPECT_GT(on_walls, 20);
}

TEST(DefaultWorldTest, SomeIdsMissingOrWorn) {
  const World world = BuildWorld(DefaultScenario().world, 1);
  int missing = 0, worn = 0;
  std::set<std::string> ids;
  for (const WorldSlot& s : world.slots) {
    missing += s.painted_id.empty();
    worn += !s.painted_id.empty() && !s.id_legible;
    if (!s.painted_id.empty()) {
      EXPECT_TRUE(ids.insert(s.painted_id).second) << s.painted_id;
    }
  }
  EXPECT_GT(missing + worn, 0);
  EXPECT_LT(missing + worn, 25);
}

TEST(WorldTest, SameSeedSameWorldOtherSeedOtherIds) {
  const World a = BuildWorld(DefaultScenario().world, 5);
  const World b = BuildWorld(DefaultScenario().world, 5);
  const World c = BuildWorld(DefaultScenario().world, 6);
  ASSERT_EQ(a.slots.size(), b.slots.size());
  bool differs = false;
  for (size_t i = 0; i < a.slots.size(); ++i) {
    EXPECT_EQ(a.slots[i].painted_id, b.slots[i].painted_id);
    EXPECT_EQ(a.slots[i].corners_map[2], b.slots[i].corners_map[2]);
    differs |= a.slots[i].painted_id != c.slots[i].painted_id ||
               a.slots[i].id_legible != c.slots[i].id_legible;
  }
  EXPECT_TRUE(differs);
}

TEST(WorldTest, InvalidConfigThrowsNamingTheField) {
  WorldConfig config = DefaultScenario().world;
  config.rows[1].depth_m = -1.0;
  try {
    BuildWorld(config, 1);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("world.rows[1].depth_m"), std::string::npos);
  }
}

TEST(WorldTest, OverlappingIdRangesAreRejected) {
  WorldConfig config = DefaultScenario().world;
  config.rows[1].first_id = 24;  // row A ends at 24
  std::string error;
  EXPECT_FALSE(config.IsValid(&error));
  EXPECT_NE(error.find("world.rows[1].first_id"), std::string::npos) << error;
  config.rows[1].first_id = 25;
  EXPECT_TRUE(config.IsValid(&error)) << error;
}

// The vehicle's message reaches the scenario's (it once printed garbage:
// a pointer into the message taken before the message was written).
TEST(WorldTest, InvalidVehicleIsNamedWithItsOwnMessage) {
  ScenarioConfig config = DefaultScenario();
  config.vehicle.wheelbase_m = -1.0;
  std::string error;
  EXPECT_FALSE(config.IsValid(&error));
  EXPECT_EQ(error, "vehicle: wheelbase_m must be in (0.5, 10)");
}

TEST(WorldTest, PillarBlocksLineOfSight) {
  World world;
  world.pillars.push_back({{5.0, 0.0}, 0.3});
  EXPECT_TRUE(SegmentBlocked(world, {0, 0}, {10, 0}, -1, -1));
  EXPECT_FALSE(SegmentBlocked(world, {0, 0.5}, {10, 0.5}, -1, -1));
  EXPECT_FALSE(SegmentBlocked(world, {0, 0}, {10, 0}, -1, 0));
}

TEST(WorldTest, GroundTruthMapKeepsSlotOrderAndTagMounts) {
  const World world = BuildWorld(DefaultScenario().world, 1);
  const SemanticMap map = ToSemanticMap(world);
  ASSERT_EQ(map.slots.size(), world.slots.size());
  EXPECT_EQ(map.slots[7].id, world.slots[7].painted_id);
  ASSERT_EQ(map.tags.size(), world.tags.size());
  for (const MapTag& tag : map.tags) {
    ASSERT_GE(tag.obstacle_index, 0);
    ASSERT_LT(tag.obstacle_index, static_cast<int>(map.obstacles.size()));
  }
}

}  // namespace
}  // namespace parkslam::sim

namespace parkslam::sim {
namespace {

TEST(WorldChangesTest, MovesAndRepaintsTheShareOfSlotsAndMovesAndRemovesTags) {
  WorldConfig config = DefaultScenario().world;
  const World before = BuildWorld(config, 1);
  config.changes.moved_slot_share = 0.05;
  config.changes.repainted_slot_share = 0.05;
  config.changes.moved_tags = 2;
  config.changes.removed_tags = 1;
  const World after = BuildWorld(config, 1);
  ASSERT_EQ(after.slots.size(), before.slots.size());
  int named = 0, moved = 0, repainted = 0;
  std::set<std::string> ids;
  for (size_t i = 0; i < before.slots.size(); ++i) {
    const WorldSlot& a = before.slots[i];
    const WorldSlot& b = after.slots[i];
    named += a.painted_id.empty() ? 0 : 1;
    if (!b.painted_id.empty()) {
      EXPECT_TRUE(ids.insert(b.painted_id).second) << b.painted_id;
    }
    const double shift_m = (b.corners_map[0] - a.corners_map[0]).norm();
    if (a.painted_id != b.painted_id) {
      ++repainted;
      EXPECT_LT(shift_m, 1e-12);  // repainted where it was
      EXPECT_FALSE(a.painted_id.empty());
      continue;
    }
    if (shift_m < 1e-12) continue;
    ++moved;
    // Towards the aisle: the entrance moves away from the back.
    const Eigen::Vector2d depth = a.corners_map[3] - a.corners_map[0];
    EXPECT_NEAR(shift_m, 0.5, 1e-9);
    EXPECT_LT((b.corners_map[0] - a.corners_map[0]).dot(depth), 0.0);
    for (int k = 1; k < 4; ++k) {
      EXPECT_NEAR((b.corners_map[k] - a.corners_map[k]).norm(), 0.5, 1e-9);
    }
  }
  EXPECT_EQ(moved, static_cast<int>(std::lround(0.05 * named)));
  EXPECT_EQ(repainted, static_cast<int>(std::lround(0.05 * named)));

  ASSERT_EQ(after.tags.size(), before.tags.size() - 1);
  int tags_moved = 0;
  for (const WorldTag& b : after.tags) {
    const auto a = std::find_if(before.tags.begin(), before.tags.end(),
                                [&](const WorldTag& t) { return t.tag_id == b.tag_id; });
    ASSERT_NE(a, before.tags.end());
    if ((a->p_map - b.p_map).norm() > 1e-9) {
      ++tags_moved;
      EXPECT_EQ(a->mount_index, b.mount_index);  // on the same wall or pillar
    }
  }
  EXPECT_EQ(tags_moved, 2);
  // The changes have their own seed: the same lot changes the same way.
  const World again = BuildWorld(config, 1);
  for (size_t i = 0; i < after.slots.size(); ++i) {
    EXPECT_EQ(again.slots[i].painted_id, after.slots[i].painted_id);
  }
}

TEST(WorldChangesTest, RejectsSharesBeyondOne) {
  WorldConfig config = DefaultScenario().world;
  config.changes.moved_slot_share = 0.6;
  config.changes.repainted_slot_share = 0.6;
  std::string error;
  EXPECT_FALSE(config.IsValid(&error));
  EXPECT_NE(error.find("world.changes.repainted_slot_share"), std::string::npos) << error;
  config.changes.repainted_slot_share = 0.0;
  config.changes.removed_tags = -1;
  EXPECT_FALSE(config.IsValid(&error));
  EXPECT_NE(error.find("world.changes.removed_tags"), std::string::npos) << error;
}

}  // namespace
}  // namespace parkslam::sim
