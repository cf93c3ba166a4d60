// Every scenario shipped in config/worlds loads and validates (STYLE.md,
// practice 5).

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <filesystem>
#include <limits>
#include <string>

#include "parkslam/io/io_error.h"
#include "parkslam/io/scenario_yaml.h"
#include "parkslam/sim/world.h"

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

// Depth of p inside the convex, counter-clockwise polygon c (negative:
// outside), metres.
double DepthInside(const std::array<Eigen::Vector2d, 4>& c, const Eigen::Vector2d& p) {
  double depth = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d edge = (c[(i + 1) % 4] - c[i]).normalized();
    const Eigen::Vector2d to_p = p - c[i];
    depth = std::min(depth, edge.x() * to_p.y() - edge.y() * to_p.x());
  }
  return depth;
}

// The lot without tags and with slots that vary by row: it builds, its
// slots stay inside the hall and clear of one another however deep a row
// was drawn, and no tag hangs anywhere.
TEST(ShippedConfigTest, VariedWorldHasNoTagsAndSlotsClearOfEachOther) {
  const sim::ScenarioConfig config =
      LoadScenarioFile(std::filesystem::path(PARKSLAM_CONFIG_DIR) / "worlds" / "varied.yaml");
  EXPECT_TRUE(config.world.slot_variation.enabled);
  const sim::World world = sim::BuildWorld(config.world);
  EXPECT_TRUE(world.tags.empty());
  EXPECT_EQ(world.slots.size(), 131u);  // rows of 22, 22, 22, 19, 22, 10 and 14
  const sim::RegionConfig& hall = config.world.hall;
  for (size_t a = 0; a < world.slots.size(); ++a) {
    const sim::WorldSlot& slot = world.slots[a];
    for (const Eigen::Vector2d& p : slot.corners_map) {
      EXPECT_TRUE(p.x() >= hall.min_x_m && p.x() <= hall.max_x_m && p.y() >= hall.min_y_m &&
                  p.y() <= hall.max_y_m)
          << slot.painted_id;
    }
    for (size_t b = 0; b < world.slots.size(); ++b) {
      if (a == b) continue;
      Eigen::Vector2d centre = Eigen::Vector2d::Zero();
      for (const Eigen::Vector2d& p : world.slots[b].corners_map) {
        EXPECT_LT(DepthInside(slot.corners_map, p), 0.05)
            << world.slots[b].painted_id << " reaches into " << slot.painted_id;
        centre += p / 4;
      }
      EXPECT_LT(DepthInside(slot.corners_map, centre), 0.0);
    }
  }
}

}  // namespace
}  // namespace parkslam::io
