#include "parkslam/render/ground_raster.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "parkslam/sim/scenario_config.h"
#include "parkslam/sim/world.h"

namespace parkslam::render {
namespace {

const sim::World& DefaultWorld() {
  static const sim::World world = [] {
    const sim::ScenarioConfig scenario = sim::DefaultScenario();
    return sim::BuildWorld(scenario.world);
  }();
  return world;
}

const GroundRaster& DefaultRaster() {
  static const GroundRaster raster(DefaultWorld(), GroundRasterOptions{}, 1);
  return raster;
}

// Mean grey level inside a slot's ID box minus the mean of the concrete
// in the band just behind it (same slot, deeper), both in the raster.
double IdContrast(const GroundRaster& raster, const sim::WorldSlot& slot) {
  GroundRasterOptions options = raster.options();
  IdPlacement id = PlaceId(slot, options);
  if (id.width_m <= 0.0) {  // no ID: measure where one would be
    sim::WorldSlot with_id = slot;
    with_id.painted_id = "00";
    id = PlaceId(with_id, options);
  }
  const auto mean_over = [&](const Eigen::Vector2d& center) {
    double sum = 0.0;
    int n = 0;
    for (double u = -0.5; u <= 0.5; u += 0.02) {
      for (double v = -0.5; v <= 0.5; v += 0.02) {
        sum += raster.At(center + id.right_map * (u * id.width_m) + id.up_map * (v * id.height_m));
        ++n;
      }
    }
    return sum / n;
  };
  return mean_over(id.center_map) - mean_over(id.center_map + id.up_map * 1.2);
}

TEST(GroundRasterTest, SameSeedSameBytes) {
  GroundRasterOptions options;
  const GroundRaster a(DefaultWorld(), options, 7);
  const GroundRaster b(DefaultWorld(), options, 7);
  ASSERT_EQ(a.image().size(), b.image().size());
  EXPECT_EQ(cv::norm(a.image(), b.image(), cv::NORM_INF), 0.0);
  const GroundRaster c(DefaultWorld(), options, 8);
  EXPECT_GT(cv::norm(a.image(), c.image(), cv::NORM_L1), 0.0);
}

TEST(GroundRasterTest, SeparatingLineIsPaintedAndConcreteBesideItIsNot) {
  const GroundRaster& raster = DefaultRaster();
  const sim::WorldSlot& slot = DefaultWorld().slots[1];
  const Eigen::Vector2d entrance = slot.corners_map[1];
  const Eigen::Vector2d side = (slot.corners_map[2] - entrance).normalized();
  const Eigen::Vector2d across = (slot.corners_map[1] - slot.corners_map[0]).normalized();
  const Eigen::Vector2d on_line = entrance + 2.0 * side;
  EXPECT_GT(raster.At(on_line), 190);
  EXPECT_GT(raster.At(on_line + 0.06 * across), 190);  // half of the 15 cm width
  EXPECT_LT(raster.At(on_line + 0.3 * across), 140);
  EXPECT_LT(raster.At(on_line - 0.3 * across), 140);
}

TEST(GroundRasterTest, EntranceIsOpenBetweenTheStubs) {
  const GroundRaster& raster = DefaultRaster();
  const sim::WorldSlot& slot = DefaultWorld().slots[1];
  const Eigen::Vector2d c0 = slot.corners_map[0], c1 = slot.corners_map[1];
  const Eigen::Vector2d e = (c1 - c0).normalized();
  EXPECT_GT(raster.At(c0 + 0.3 * e), 190);  // stub, 0.5 m long
  EXPECT_LT(raster.At(c0 + 0.7 * e), 140);  // open entrance
  EXPECT_LT(raster.At((c0 + c1) / 2), 140);
  EXPECT_GT(raster.At(c1 - 0.3 * e), 190);
}

TEST(GroundRasterTest, WornIdIsFainterThanLegibleAndMissingIdIsNotDrawn) {
  const GroundRaster& raster = DefaultRaster();
  double legible_sum = 0.0, worn_sum = 0.0, missing_sum = 0.0;
  int legible = 0, worn = 0, missing = 0;
  for (const sim::WorldSlot& slot : DefaultWorld().slots) {
    const double contrast = IdContrast(raster, slot);
    if (slot.painted_id.empty()) {
      missing_sum += std::abs(contrast);
      ++missing;
    } else if (slot.id_legible) {
      legible_sum += contrast;
      ++legible;
    } else {
      worn_sum += contrast;
      ++worn;
    }
  }
  ASSERT_GT(worn, 0);
  ASSERT_GT(missing, 0);
  const double legible_mean = legible_sum / legible, worn_mean = worn_sum / worn;
  EXPECT_GT(legible_mean, 25.0);
  EXPECT_GT(worn_mean, 2.0);  // still there, faintly
  EXPECT_LT(worn_mean, 0.45 * legible_mean);
  EXPECT_LT(missing_sum / missing, 6.0);
}

TEST(GroundRasterTest, WallsAndPillarsAreBlack) {
  const GroundRaster& raster = DefaultRaster();
  const sim::WorldWall& wall = DefaultWorld().walls.front();
  EXPECT_EQ(raster.At((wall.a_map + wall.b_map) / 2), 0);
  EXPECT_EQ(raster.At(DefaultWorld().pillars.front().center_map), 0);
}

TEST(GroundRasterTest, PixelAndMapCoordinatesAreInverse) {
  const GroundRaster& raster = DefaultRaster();
  const Eigen::Vector2d p(12.345, 6.789);
  EXPECT_LT((raster.MapOf(raster.PixelOf(p)) - p).norm(), 1e-9);
  // North up: a point further north has a smaller row.
  EXPECT_LT(raster.PixelOf({0.0, 10.0}).y(), raster.PixelOf({0.0, 9.0}).y());
}

TEST(GroundRasterTest, RejectsInvalidOptions) {
  GroundRasterOptions options;
  options.line_width_m = 0.0;
  std::string error;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("line_width_m"), std::string::npos);
  EXPECT_THROW(GroundRaster(DefaultWorld(), options, 1), std::invalid_argument);
}

}  // namespace
}  // namespace parkslam::render
