#include "parkslam/sim/world_plan.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "parkslam/common/angles.h"
#include "parkslam/sim/scenario_config.h"
#include "parkslam/sim/world.h"

namespace parkslam::sim {
namespace {

using ::testing::HasSubstr;

void ExpectSamePoint(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double tolerance_m) {
  if (tolerance_m == 0.0) {
    EXPECT_EQ(a, b);
  } else {
    EXPECT_LE((a - b).norm(), tolerance_m) << a.transpose() << " vs " << b.transpose();
  }
}

// Slots, walls, pillars and tags of two worlds are the same, positions
// exactly or within tolerance_m; a tag's yaw may differ by the rounding of
// its trip through degrees.
void ExpectSameWorld(const World& a, const World& b, double tolerance_m = 0.0) {
  ASSERT_EQ(a.slots.size(), b.slots.size());
  for (size_t i = 0; i < a.slots.size(); ++i) {
    SCOPED_TRACE("slot " + std::to_string(i));
    EXPECT_EQ(a.slots[i].kind, b.slots[i].kind);
    for (size_t k = 0; k < kSlotCorners; ++k) {
      ExpectSamePoint(a.slots[i].corners_map[k], b.slots[i].corners_map[k], tolerance_m);
    }
    EXPECT_EQ(a.slots[i].painted_id, b.slots[i].painted_id);
    EXPECT_EQ(a.slots[i].id_legible, b.slots[i].id_legible);
  }
  ASSERT_EQ(a.walls.size(), b.walls.size());
  for (size_t i = 0; i < a.walls.size(); ++i) {
    ExpectSamePoint(a.walls[i].a_map, b.walls[i].a_map, tolerance_m);
    ExpectSamePoint(a.walls[i].b_map, b.walls[i].b_map, tolerance_m);
    EXPECT_EQ(a.walls[i].normal_map, b.walls[i].normal_map);
  }
  ASSERT_EQ(a.pillars.size(), b.pillars.size());
  for (size_t i = 0; i < a.pillars.size(); ++i) {
    ExpectSamePoint(a.pillars[i].center_map, b.pillars[i].center_map, tolerance_m);
    EXPECT_NEAR(a.pillars[i].half_size_m, b.pillars[i].half_size_m, tolerance_m);
  }
  ASSERT_EQ(a.tags.size(), b.tags.size());
  for (size_t i = 0; i < a.tags.size(); ++i) {
    SCOPED_TRACE("tag " + std::to_string(i));
    EXPECT_EQ(a.tags[i].tag_id, b.tags[i].tag_id);
    ExpectSamePoint(a.tags[i].p_map, b.tags[i].p_map, tolerance_m);
    EXPECT_NEAR(a.tags[i].normal_yaw_rad, b.tags[i].normal_yaw_rad, 1e-12);
    EXPECT_EQ(a.tags[i].size_m, b.tags[i].size_m);
    EXPECT_EQ(a.tags[i].on_pillar, b.tags[i].on_pillar);
    EXPECT_EQ(a.tags[i].mount_index, b.tags[i].mount_index);
  }
}

// A plan of one slot, one wall with a tag, one pillar.
WorldPlan OneSlotPlan() {
  WorldPlan plan;
  plan.slots.push_back({"perpendicular", {{2.5, 5.3}, {0, 5.3}, {0, 0}, {2.5, 0}}, "01", true});
  plan.walls.push_back({{-5, 0}, {20, 0}, {0, 1}});
  plan.pillars.push_back({{10, 10}, 0.3});
  plan.tags.push_back({4, {5, 0}, 90.0, 0.488, "wall", 0});
  return plan;
}

const RegionConfig kHall{-5, 0, 20, 20};

std::string PlanError(const WorldPlan& plan) {
  std::string error;
  EXPECT_FALSE(IsValidPlan(plan, kHall, "world.plan", &error));
  return error;
}

TEST(WorldPlanTest, DefaultWorldRoundTripsThroughItsPlan) {
  const WorldConfig config = DefaultScenario().world;
  const World world = BuildWorld(config, 1);
  const WorldPlan plan = PlanFromWorld(world, FloorRegions(config));
  std::string error;
  ASSERT_TRUE(IsValidPlan(plan, config.hall, "world.plan", &error)) << error;
  const World rebuilt = BuildWorldFromPlan(plan, config.name, config.hall);
  ExpectSameWorld(world, rebuilt);
  EXPECT_EQ(rebuilt.name, world.name);
  EXPECT_DOUBLE_EQ(rebuilt.floor_area_m2, world.floor_area_m2);
  EXPECT_GT(world.slots.size(), 100u);
  EXPECT_GT(world.tags.size(), 50u);
}

TEST(WorldPlanTest, BuildWorldTakesThePlanOfItsConfig) {
  WorldConfig config;
  config.name = "one";
  config.hall = kHall;
  config.corridor = false;
  config.plan = OneSlotPlan();
  const World world = BuildWorld(config, 3);
  ASSERT_EQ(world.slots.size(), 1u);
  EXPECT_EQ(world.slots[0].painted_id, "01");
  EXPECT_EQ(world.slots[0].corners_map[1], Eigen::Vector2d(0, 5.3));
  ASSERT_EQ(world.tags.size(), 1u);
  EXPECT_EQ(world.tags[0].tag_id, 4);
  EXPECT_DOUBLE_EQ(world.tags[0].normal_yaw_rad, kPi / 2);
  EXPECT_DOUBLE_EQ(world.floor_area_m2, 25.0 * 20.0);
}

TEST(WorldPlanTest, GoodPlanIsValid) {
  std::string error;
  EXPECT_TRUE(IsValidPlan(OneSlotPlan(), kHall, "world.plan", &error)) << error;
}

TEST(WorldPlanTest, ClockwiseCornersAreRefused) {
  WorldPlan plan = OneSlotPlan();
  std::swap(plan.slots[0].corners_m[1], plan.slots[0].corners_m[3]);
  EXPECT_THAT(PlanError(plan), HasSubstr("world.plan.slots[0].corners_m: corner 0 does not turn "
                                         "left: the corners must go round counter-clockwise"));
}

TEST(WorldPlanTest, ThreeCornersAreRefused) {
  WorldPlan plan = OneSlotPlan();
  plan.slots[0].corners_m.pop_back();
  EXPECT_EQ(PlanError(plan), "world.plan.slots[0].corners_m: needs four corners, got 3");
}

TEST(WorldPlanTest, SlotTooSmallOrSkewedIsRefused) {
  WorldPlan small = OneSlotPlan();
  small.slots[0].corners_m = {{1.2, 5.3}, {0, 5.3}, {0, 0}, {1.2, 0}};
  EXPECT_THAT(PlanError(small), HasSubstr("side 0-1 is 1.2 m long"));
  // Just within and just beyond the parallelogram tolerance (0.3 m between
  // the diagonals' midpoints: half the far side's shift).
  WorldPlan skewed = OneSlotPlan();
  skewed.slots[0].corners_m[2].x() = -0.58;
  std::string error;
  EXPECT_TRUE(IsValidPlan(skewed, kHall, "world.plan", &error)) << error;
  skewed.slots[0].corners_m[2].x() = -0.62;
  EXPECT_THAT(PlanError(skewed), HasSubstr("not a parallelogram"));
}

TEST(WorldPlanTest, DuplicateIdsAreRefused) {
  WorldPlan plan = OneSlotPlan();
  plan.slots.push_back(plan.slots[0]);
  for (Eigen::Vector2d& p : plan.slots[1].corners_m) p.x() += 2.5;
  EXPECT_EQ(PlanError(plan), "world.plan.slots[1].painted_id: '01' is painted on another slot too");
  plan.slots[1].painted_id.clear();  // unpainted slots may be many
  std::string error;
  EXPECT_TRUE(IsValidPlan(plan, kHall, "world.plan", &error)) << error;

  plan.tags.push_back(plan.tags[0]);
  EXPECT_EQ(PlanError(plan), "world.plan.tags[1].id: 4 is the ID of another tag too");
}

TEST(WorldPlanTest, TagsMustHangOnTheirMount) {
  WorldPlan plan = OneSlotPlan();
  plan.tags[0].mount_index = 1;
  EXPECT_EQ(PlanError(plan), "world.plan.tags[0].mount_index: names no wall (the plan has 1)");
  plan.tags[0] = {4, {10, 10.35}, 90.0, 0.488, "pillar", 0};
  std::string error;
  EXPECT_TRUE(IsValidPlan(plan, kHall, "world.plan", &error)) << error;
  plan.tags[0].p_m.y() = 10.45;
  EXPECT_THAT(PlanError(plan), HasSubstr("world.plan.tags[0].p_m: lies 0.15 m from the face"));
  plan.tags[0].mount = "ceiling";
  EXPECT_EQ(PlanError(plan), "world.plan.tags[0].mount: must be wall, pillar or none");
}

TEST(WorldPlanTest, WallNormalMustBeUnitAndPerpendicular) {
  WorldPlan plan = OneSlotPlan();
  plan.walls[0].normal = {0.1, 1.0};
  EXPECT_EQ(PlanError(plan),
            "world.plan.walls[0].normal: must be a unit vector perpendicular to the wall");
}

TEST(WorldPlanTest, RouteMustStayOnTheFloorAndMissWalls) {
  const WorldPlan plan = OneSlotPlan();
  const World world = BuildWorldFromPlan(plan, "one", kHall);
  const std::vector<RegionConfig> floor = PlanFloor(plan, kHall);
  std::string error;
  EXPECT_TRUE(IsDrivableRoute({{0, 8}, {18, 8}, {18, 15}}, floor, world, "route", &error)) << error;
  EXPECT_FALSE(IsDrivableRoute({{0, 8}, {25, 8}}, floor, world, "route", &error));
  EXPECT_EQ(error, "route[1]: (25, 8) is off the floor");
  EXPECT_FALSE(IsDrivableRoute({{5, 10}, {15, 10}}, floor, world, "route", &error));
  EXPECT_EQ(error, "route[0] to [1]: the leg runs through a wall or pillar");
  // Two floor rectangles in an L: the diagonal across the corner leaves it.
  const std::vector<RegionConfig> l_floor{{0, 0, 10, 3}, {0, 0, 3, 10}};
  EXPECT_FALSE(IsDrivableRoute({{9, 1}, {1, 9}}, l_floor, world, "route", &error));
  EXPECT_EQ(error, "route[0] to [1]: the leg leaves the floor");
}

TEST(WorldPlanTest, PlanFromTheTruthMapGivesTheWorldBack) {
  const WorldConfig config = DefaultScenario().world;
  const World world = BuildWorld(config, 1);
  const WorldPlan plan = PlanFromMap(ToSemanticMap(world));
  const RegionConfig hall = MapBounds(ToSemanticMap(world), 1.0);
  EXPECT_DOUBLE_EQ(hall.min_x_m, -config.corridor_length_m - 1.0);
  EXPECT_DOUBLE_EQ(hall.max_y_m, config.hall.max_y_m + 1.0);
  // Pillars pass through their corners: equal to rounding.
  ExpectSameWorld(world, BuildWorldFromPlan(plan, config.name, hall), 1e-12);
}

}  // namespace
}  // namespace parkslam::sim
