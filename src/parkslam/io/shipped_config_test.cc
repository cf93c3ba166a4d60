// Every scenario shipped in config/worlds loads and validates (STYLE.md,
// practice 5).

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "parkslam/io/io_error.h"
#include "parkslam/io/scenario_yaml.h"

namespace parkslam::io {
namespace {

TEST(ShippedConfigTest, EveryWorldFileLoadsAndIsValid) {
  const std::filesystem::path worlds = std::filesystem::path(PARKSLAM_CONFIG_DIR) / "worlds";
  ASSERT_TRUE(std::filesystem::is_directory(worlds)) << worlds;
  int loaded = 0;
  for (const auto& entry : std::filesystem::directory_iterator(worlds)) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    sim::ScenarioConfig config;
    EXPECT_NO_THROW(config = LoadScenarioFile(entry.path()));
    std::string error;
    EXPECT_TRUE(config.IsValid(&error)) << error;
    ++loaded;
  }
  EXPECT_GE(loaded, 1);
}

TEST(ShippedConfigTest, SmallWorldIsSmall) {
  const sim::ScenarioConfig config =
      LoadScenarioFile(std::filesystem::path(PARKSLAM_CONFIG_DIR) / "worlds" / "small.yaml");
  EXPECT_EQ(config.world.name, "small");
  EXPECT_DOUBLE_EQ(config.world.hall.max_x_m - config.world.hall.min_x_m, 40.0);
  EXPECT_DOUBLE_EQ(config.world.hall.max_y_m - config.world.hall.min_y_m, 25.0);
  ASSERT_EQ(config.world.rows.size(), 2u);
  EXPECT_EQ(config.world.rows[0].count + config.world.rows[1].count, 20);
  EXPECT_EQ(config.world.tag_count, 10);
  EXPECT_EQ(config.route.laps, 1);
}

}  // namespace
}  // namespace parkslam::io
