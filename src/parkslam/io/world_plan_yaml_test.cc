#include "parkslam/io/world_plan_yaml.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "parkslam/io/io_error.h"
#include "parkslam/io/scenario_yaml.h"
#include "parkslam/io/test_util.h"
#include "parkslam/sim/route.h"
#include "parkslam/sim/world.h"

namespace parkslam::io {
namespace {

using testing::ErrorOf;
using ::testing::HasSubstr;

// Two perpendicular slots facing north over an aisle, a wall with a tag, a
// pillar, and a drive along the aisle.
constexpr char kGoodPlan[] = R"(name: "two_slots"
hall: {min_x_m: 0, min_y_m: 0, max_x_m: 30, max_y_m: 20}
slots:
  - {kind: "perpendicular", painted_id: "01", id_legible: true,
     corners_m: [[7.5, 5.3], [5, 5.3], [5, 0], [7.5, 0]]}
  - {kind: "perpendicular", painted_id: "", id_legible: true,
     corners_m: [[10, 5.3], [7.5, 5.3], [7.5, 0], [10, 0]]}
walls:
  - {a_m: [0, 0], b_m: [30, 0], normal: [0, 1]}
pillars:
  - {center_m: [20, 15], half_size_m: 0.3}
tags:
  - {id: 3, p_m: [2, 0], normal_yaw_deg: 90, size_m: 0.488, mount: "wall", mount_index: 0}
route:
  waypoints_m: [[2, 9], [28, 9]]
)";

std::string Replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

// The tolerance of ExpectSameWorld in sim/world_plan_test.cc: exact
// positions, a tag's yaw to the rounding of its trip through degrees.
void ExpectSameWorld(const sim::World& a, const sim::World& b) {
  ASSERT_EQ(a.slots.size(), b.slots.size());
  for (size_t i = 0; i < a.slots.size(); ++i) {
    EXPECT_EQ(a.slots[i].kind, b.slots[i].kind);
    for (size_t k = 0; k < kSlotCorners; ++k) {
      EXPECT_EQ(a.slots[i].corners_map[k], b.slots[i].corners_map[k]);
    }
    EXPECT_EQ(a.slots[i].painted_id, b.slots[i].painted_id);
    EXPECT_EQ(a.slots[i].id_legible, b.slots[i].id_legible);
  }
  ASSERT_EQ(a.walls.size(), b.walls.size());
  for (size_t i = 0; i < a.walls.size(); ++i) {
    EXPECT_EQ(a.walls[i].a_map, b.walls[i].a_map);
    EXPECT_EQ(a.walls[i].b_map, b.walls[i].b_map);
    EXPECT_EQ(a.walls[i].normal_map, b.walls[i].normal_map);
  }
  ASSERT_EQ(a.pillars.size(), b.pillars.size());
  for (size_t i = 0; i < a.pillars.size(); ++i) {
    EXPECT_EQ(a.pillars[i].center_map, b.pillars[i].center_map);
    EXPECT_EQ(a.pillars[i].half_size_m, b.pillars[i].half_size_m);
  }
  ASSERT_EQ(a.tags.size(), b.tags.size());
  for (size_t i = 0; i < a.tags.size(); ++i) {
    EXPECT_EQ(a.tags[i].tag_id, b.tags[i].tag_id);
    EXPECT_EQ(a.tags[i].p_map, b.tags[i].p_map);
    EXPECT_NEAR(a.tags[i].normal_yaw_rad, b.tags[i].normal_yaw_rad, 1e-12);
    EXPECT_EQ(a.tags[i].size_m, b.tags[i].size_m);
    EXPECT_EQ(a.tags[i].on_pillar, b.tags[i].on_pillar);
    EXPECT_EQ(a.tags[i].mount_index, b.tags[i].mount_index);
  }
}

TEST(WorldPlanYamlTest, GoodPlanBecomesAScenario) {
  const sim::ScenarioConfig scenario =
      ScenarioFromPlan(PlanFromYaml(kGoodPlan, "plan.yaml"), "plan.yaml");
  EXPECT_EQ(scenario.world.name, "two_slots");
  EXPECT_TRUE(scenario.world.rows.empty());
  EXPECT_FALSE(scenario.world.corridor);
  ASSERT_TRUE(scenario.world.plan.has_value());
  const sim::World world = sim::BuildWorld(scenario.world, 7);
  ASSERT_EQ(world.slots.size(), 2u);
  EXPECT_EQ(world.slots[0].painted_id, "01");
  EXPECT_EQ(world.slots[1].painted_id, "");
  EXPECT_EQ(world.slots[1].corners_map[3], Eigen::Vector2d(10, 0));
  ASSERT_EQ(world.tags.size(), 1u);
  EXPECT_EQ(world.tags[0].tag_id, 3);
  EXPECT_EQ(world.pillars.size(), 1u);
  EXPECT_DOUBLE_EQ(world.floor_area_m2, 600.0);
  EXPECT_EQ(sim::RouteWaypoints(scenario.route), (std::vector<Eigen::Vector2d>{{2, 9}, {28, 9}}));
  EXPECT_EQ(scenario.route.cruise_speed_kmh, 9.0);
}

TEST(WorldPlanYamlTest, UnknownKeyIsNamedWithItsLine) {
  EXPECT_EQ(
      ErrorOf([] { PlanFromYaml(Replaced(kGoodPlan, "corners_m", "corner_m"), "plan.yaml"); }),
      "plan.yaml:5: slots[0].corner_m: unknown key (did you mean 'corners_m'?)");
  EXPECT_THAT(ErrorOf([] { PlanFromYaml(Replaced(kGoodPlan, "pillars:", "pilars:"), "p.yaml"); }),
              HasSubstr("p.yaml:10: pilars: unknown key (did you mean 'pillars'?)"));
  EXPECT_THAT(
      ErrorOf([] { PlanFromYaml(Replaced(kGoodPlan, "size_m: 0.488", "size_m: big"), "p.yaml"); }),
      HasSubstr("tags[0].size_m: expected a number, got 'big'"));
}

TEST(WorldPlanYamlTest, BadCornersAreNamed) {
  const std::string clockwise = Replaced(kGoodPlan, "[[7.5, 5.3], [5, 5.3], [5, 0], [7.5, 0]]",
                                         "[[5, 5.3], [7.5, 5.3], [7.5, 0], [5, 0]]");
  EXPECT_THAT(ErrorOf([&] { ScenarioFromPlan(PlanFromYaml(clockwise, "p.yaml"), "p.yaml"); }),
              HasSubstr("p.yaml: slots[0].corners_m: corner 0 does not turn left"));
  const std::string three = Replaced(kGoodPlan, "[[7.5, 5.3], [5, 5.3], [5, 0], [7.5, 0]]",
                                     "[[7.5, 5.3], [5, 5.3], [5, 0]]");
  EXPECT_EQ(ErrorOf([&] { ScenarioFromPlan(PlanFromYaml(three, "p.yaml"), "p.yaml"); }),
            "p.yaml: slots[0].corners_m: needs four corners, got 3");
}

TEST(WorldPlanYamlTest, RouteOffTheFloorOrThroughAWallIsNamed) {
  const std::string off = Replaced(kGoodPlan, "[[2, 9], [28, 9]]", "[[2, 9], [35, 9]]");
  EXPECT_EQ(ErrorOf([&] { ScenarioFromPlan(PlanFromYaml(off, "p.yaml"), "p.yaml"); }),
            "p.yaml: route.waypoints_m[1]: (35, 9) is off the floor");
  const std::string through = Replaced(kGoodPlan, "[[2, 9], [28, 9]]", "[[15, 15], [25, 15]]");
  EXPECT_EQ(ErrorOf([&] { ScenarioFromPlan(PlanFromYaml(through, "p.yaml"), "p.yaml"); }),
            "p.yaml: route.waypoints_m[0] to [1]: the leg runs through a wall or pillar");
}

// The built-in small world -> plan file -> world: the same slots, walls,
// pillars and tags, and the same waypoints.
TEST(WorldPlanYamlTest, SmallWorldRoundTripsThroughAPlanFile) {
  const sim::ScenarioConfig small =
      LoadScenarioFile(std::filesystem::path(PARKSLAM_CONFIG_DIR) / "worlds" / "small.yaml");
  const std::string text = PlanToYaml(PlanFromScenario(small));
  const sim::ScenarioConfig from_plan =
      ScenarioFromPlan(PlanFromYaml(text, "small_plan.yaml"), "small_plan.yaml");
  const sim::World original = sim::BuildWorld(small.world);
  const sim::World rebuilt = sim::BuildWorld(from_plan.world, 99);
  ExpectSameWorld(original, rebuilt);
  EXPECT_EQ(rebuilt.floor_area_m2, original.floor_area_m2);
  EXPECT_EQ(sim::RouteWaypoints(from_plan.route), sim::RouteWaypoints(small.route));
  EXPECT_GT(original.tags.size(), 0u);
  EXPECT_GT(original.pillars.size(), 0u);
}

// A scenario holding a plan writes it whole (a dataset's scenario needs no
// other file) and reads it back; one without writes no plan key.
TEST(WorldPlanYamlTest, ScenarioWithAPlanRoundTrips) {
  const sim::ScenarioConfig scenario =
      ScenarioFromPlan(PlanFromYaml(kGoodPlan, "plan.yaml"), "plan.yaml");
  const std::string text = ScenarioToYaml(scenario);
  EXPECT_THAT(text, HasSubstr("\n  plan:\n    floor: []\n    slots:\n"));
  const sim::ScenarioConfig read = ScenarioFromYaml(text, sim::DefaultScenario(), "s.yaml");
  ASSERT_TRUE(read.world.plan.has_value());
  ExpectSameWorld(sim::BuildWorld(scenario.world, 1), sim::BuildWorld(read.world, 1));
  EXPECT_EQ(ScenarioToYaml(read), text);
  EXPECT_THAT(ScenarioToYaml(sim::DefaultScenario()), ::testing::Not(HasSubstr("plan")));
}

TEST(WorldPlanYamlTest, SetReachesIntoAPlanOnlyWhenThereIsOne) {
  sim::ScenarioConfig scenario =
      ScenarioFromPlan(PlanFromYaml(kGoodPlan, "plan.yaml"), "plan.yaml");
  ApplyOverride(&scenario, "world.plan.slots[1].painted_id=\"02\"");
  EXPECT_EQ(scenario.world.plan->slots[1].painted_id, "02");
  sim::ScenarioConfig generated = sim::DefaultScenario();
  EXPECT_EQ(ErrorOf([&] { ApplyOverride(&generated, "world.plan.slots[0].painted_id=\"7\""); }),
            "--set: world.plan: not set, so none of its keys can be set");
}

TEST(WorldPlanYamlTest, EveryShippedPlanLoads) {
  const std::filesystem::path plans = std::filesystem::path(PARKSLAM_CONFIG_DIR) / "plans";
  int loaded = 0;
  for (const auto& entry : std::filesystem::directory_iterator(plans)) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    EXPECT_NO_THROW(LoadPlanFile(entry.path()));
    ++loaded;
  }
  EXPECT_GE(loaded, 1);
}

}  // namespace
}  // namespace parkslam::io
