#include "parkslam/render/light_field.h"

#include <gtest/gtest.h>

#include "parkslam/sim/scenario_config.h"

namespace parkslam::render {
namespace {

sim::World LitWorld() {
  const sim::ScenarioConfig scenario = sim::DefaultScenario();
  return sim::BuildWorld(scenario.world);
}

LightField FieldOver(const sim::World& world, const LightFieldOptions& options) {
  return LightField(world, -45.0, 55.0, 140.0, 60.0, options);
}

TEST(LightFieldTest, TheDefaultLotIsOpenOnlyAtTheCorridorEnd) {
  const auto openings = WallOpenings(LitWorld());
  ASSERT_EQ(openings.size(), 1u);
  const Eigen::Vector2d mid = (openings[0].first + openings[0].second) / 2;
  EXPECT_NEAR(mid.x(), -40.0, 1e-9);
  EXPECT_NEAR(mid.y(), 9.1, 1e-9);
  EXPECT_NEAR((openings[0].first - openings[0].second).norm(), 3.0, 1e-9);
}

TEST(LightFieldTest, DaylightOverexposesTheEntranceOnly) {
  const sim::World world = LitWorld();
  LightFieldOptions options;
  options.uneven_light = 0.0;
  options.overexposure_near_entrance = 0.5;
  const LightField field = FieldOver(world, options);
  EXPECT_NEAR(field.At(-40.0, 9.1), 2.5, 0.05);  // 1 + 3 x 0.5 at the opening
  EXPECT_NEAR(field.At(-30.0, 9.1), 1.2, 0.05);  // 10 m in: 1 + 1.5 exp(-2)
  EXPECT_NEAR(field.At(40.0, 25.0), 1.0, 1e-3);  // deep in the hall
  options.overexposure_near_entrance = 0.0;
  EXPECT_NEAR(FieldOver(world, options).At(-40.0, 9.1), 1.0, 1e-3);
}

TEST(LightFieldTest, UnevenLightMakesPoolsUnderTheLamps) {
  const sim::World world = LitWorld();
  LightFieldOptions options;
  options.overexposure_near_entrance = 0.0;
  options.uneven_light = 0.3;
  const LightField field = FieldOver(world, options);
  // Lamps sit at hall corner + (3, 3) + 6 m steps.
  const double under = field.At(45.0, 27.0), between = field.At(48.0, 30.0);
  EXPECT_GT(under, 1.05);
  EXPECT_LT(between, 0.95);
  EXPECT_TRUE(field.IsLamp(45.0f, 27.0f));
  EXPECT_TRUE(field.IsLamp(45.5f, 27.05f));
  EXPECT_FALSE(field.IsLamp(45.0f, 27.2f));
  EXPECT_FALSE(field.IsLamp(48.0f, 30.0f));
  options.uneven_light = 0.0;
  EXPECT_NEAR(FieldOver(world, options).At(48.0, 30.0), 1.0, 1e-3);
}

}  // namespace
}  // namespace parkslam::render
