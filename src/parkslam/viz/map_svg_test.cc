#include "parkslam/viz/map_svg.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "parkslam/common/angles.h"

namespace parkslam::viz {
namespace {

constexpr double kSlotWidthM = 2.5;
constexpr double kSlotDepthM = 5.0;

int OccurrencesOf(const std::string& text, const std::string& needle) {
  int count = 0;
  for (size_t at = text.find(needle); at != std::string::npos;
       at = text.find(needle, at + needle.size())) {
    ++count;
  }
  return count;
}

// The text between `<g id="<id>"` and the group's closing tag.
std::string GroupBody(const std::string& svg, const std::string& id) {
  const size_t begin = svg.find("<g id=\"" + id + "\"");
  if (begin == std::string::npos) return "";
  const size_t end = svg.find("</g>", begin);
  return svg.substr(begin, end - begin);
}

// A perpendicular slot whose entrance runs along +x from (x, y).
MapSlot MakeSlot(const std::string& id, double x, double y) {
  MapSlot slot;
  slot.id = id;
  slot.corners_map = {Eigen::Vector2d(x, y), Eigen::Vector2d(x + kSlotWidthM, y),
                      Eigen::Vector2d(x + kSlotWidthM, y + kSlotDepthM),
                      Eigen::Vector2d(x, y + kSlotDepthM)};
  return slot;
}

// Rows of 20 slots, IDs 100, 101, ..., with a pillar every 3 slots, walls
// round the lot and a tag on every pillar.
SemanticMap MakeLot(int slot_count) {
  SemanticMap map;
  for (int i = 0; i < slot_count; ++i) {
    const double x = kSlotWidthM * (i % 20);
    const double y = 12.0 * (i / 20);
    map.slots.push_back(MakeSlot(std::to_string(100 + i), x, y));
    if (i % 3 == 0) {
      map.obstacles.push_back(
          {ObstacleKind::kPillar,
           {{x - 0.3, y + 5.2}, {x + 0.3, y + 5.2}, {x + 0.3, y + 5.8}, {x - 0.3, y + 5.8}}});
      map.tags.push_back({.tag_id = i,
                          .p_map = Eigen::Vector2d(x, y + 5.1),
                          .yaw_map_rad = -kPi / 2,
                          .obstacle_index = static_cast<int>(map.obstacles.size()) - 1,
                          .last_confirmed = {}});
    }
  }
  map.obstacles.push_back({ObstacleKind::kWall, {{-5.0, -8.0}, {55.0, -8.0}}});
  return map;
}

// A 10-minute drive at 100 Hz, weaving through the lot.
Trajectory MakeDrive(double phase) {
  Trajectory trajectory;
  for (int i = 0; i < 60000; ++i) {
    const double s = 1e-4 * i;
    trajectory.push_back(
        {i * (kNanosecondsPerSecond / 100),
         SE2(25.0 + 24.0 * std::sin(2.0 * s + phase), 35.0 + 30.0 * std::sin(3.0 * s), 0.0)});
  }
  return trajectory;
}

::testing::AssertionResult IsWellFormed(const std::string& svg) {
  if (svg.rfind("<?xml", 0) != 0 && svg.rfind("<svg", 0) != 0) {
    return ::testing::AssertionFailure() << "does not start with <?xml or <svg";
  }
  const size_t last = svg.find_last_not_of(" \n");
  if (last == std::string::npos || svg.compare(last - 5, 6, "</svg>") != 0) {
    return ::testing::AssertionFailure() << "does not end with </svg>";
  }
  const int opened = OccurrencesOf(svg, "<g>") + OccurrencesOf(svg, "<g ");
  const int closed = OccurrencesOf(svg, "</g>");
  if (opened != closed) {
    return ::testing::AssertionFailure() << opened << " <g> but " << closed << " </g>";
  }
  return ::testing::AssertionSuccess();
}

TEST(RenderMapSvgTest, ProducesWellFormedDocument) {
  const std::string svg =
      RenderMapSvg(MakeLot(40), {{"truth", "#2ca02c", MakeDrive(0.0)}}, {.title = "lot"});
  EXPECT_TRUE(IsWellFormed(svg));
}

TEST(RenderMapSvgTest, LabelsEverySlotWithItsId) {
  const SemanticMap map = MakeLot(40);
  const std::string svg = RenderMapSvg(map, {});
  for (const MapSlot& slot : map.slots) {
    EXPECT_NE(svg.find("fill=\"black\">" + slot.id + "</text>"), std::string::npos) << slot.id;
  }
}

TEST(RenderMapSvgTest, TemporaryIdIsOrange) {
  SemanticMap map;
  map.slots.push_back(MakeSlot("38", 0.0, 0.0));
  map.slots.push_back(MakeSlot("t7", kSlotWidthM, 0.0));
  map.slots.back().temporary = true;
  const std::string svg = RenderMapSvg(map, {});
  EXPECT_NE(svg.find("fill=\"orange\">t7</text>"), std::string::npos);
  EXPECT_NE(svg.find("fill=\"black\">38</text>"), std::string::npos);
}

TEST(RenderMapSvgTest, SlotWithoutPaintedIdIsUnlabeled) {
  SemanticMap map;
  map.slots.push_back(MakeSlot("38", 0.0, 0.0));
  map.slots.push_back(MakeSlot("", kSlotWidthM, 0.0));
  map.slots.push_back(MakeSlot("40", 2.0 * kSlotWidthM, 0.0));
  const std::string svg = RenderMapSvg(map, {});
  EXPECT_EQ(OccurrencesOf(GroupBody(svg, "slot_ids"), "<text"), 2);
}

TEST(RenderMapSvgTest, SlotIdsCanBeTurnedOff) {
  const std::string svg = RenderMapSvg(MakeLot(5), {}, {.draw_slot_ids = false});
  EXPECT_EQ(svg.find(">100</text>"), std::string::npos);
}

TEST(RenderMapSvgTest, SlotIdSitsInsideTheSlotNearItsEntrance) {
  SemanticMap map;
  map.slots.push_back(MakeSlot("38", 0.0, 0.0));
  // The slot plus 3 m is [-3, 5.5] x [-3, 8], widened to the 14 m minimum:
  // [-5.75, 8.25]. With a 30 px margin at 10 px/m the id's anchor (1.25, 1.5),
  // 0.3 of the depth behind the entrance, lands at x = 30 + 70, y = 30 + 65.
  const std::string svg = RenderMapSvg(map, {});
  EXPECT_NE(svg.find("<text x=\"100\" y=\"95\" dy=\".35em\" fill=\"black\">38<"),
            std::string::npos);
}

TEST(RenderMapSvgTest, EntranceIsThickerThanOtherEdges) {
  SemanticMap map;
  map.slots.push_back(MakeSlot("38", 0.0, 0.0));
  map.slots.push_back(MakeSlot("39", kSlotWidthM, 0.0));
  const std::string slots = GroupBody(RenderMapSvg(map, {}), "slots");
  EXPECT_EQ(OccurrencesOf(slots, "<line"), 8);
  EXPECT_EQ(OccurrencesOf(slots, "stroke-width=\"3\""), 2);
}

TEST(RenderMapSvgTest, GuessedCornersAreHollowAndTheirEdgesDashed) {
  SemanticMap map;
  map.slots.push_back(MakeSlot("38", 0.0, 0.0));
  map.slots.back().corner_observed = {true, true, false, false};
  const std::string slots = GroupBody(RenderMapSvg(map, {}), "slots");
  // Edges 1-2, 2-3 and 3-0 touch a guessed corner; the entrance does not.
  EXPECT_EQ(OccurrencesOf(slots, "stroke-dasharray"), 3);
  EXPECT_EQ(OccurrencesOf(slots, "fill=\"white\""), 2);
  EXPECT_EQ(OccurrencesOf(slots, "<circle"), 4);
}

TEST(RenderMapSvgTest, DrawsObstaclesAndTags) {
  const std::string svg = RenderMapSvg(MakeLot(6), {});
  const std::string obstacles = GroupBody(svg, "obstacles");
  EXPECT_EQ(OccurrencesOf(obstacles, "<polygon"), 2);   // pillars at slots 0 and 3
  EXPECT_EQ(OccurrencesOf(obstacles, "<polyline"), 1);  // the wall
  EXPECT_NE(obstacles.find("stroke-width=\"4\""), std::string::npos);
  const std::string tags = GroupBody(svg, "tags");
  EXPECT_EQ(OccurrencesOf(tags, "<polygon"), 2);
  EXPECT_NE(tags.find(">3</text>"), std::string::npos);
}

TEST(RenderMapSvgTest, BoxCoversMapWithThreeMetreBorder) {
  SemanticMap map;
  map.obstacles.push_back({ObstacleKind::kWall, {{0.0, 0.0}, {40.0, 20.0}}});
  // (40 + 6) m * 10 px/m + 2 * 30 px by (20 + 6) * 10 + 60.
  EXPECT_NE(RenderMapSvg(map, {}).find("width=\"520\" height=\"320\""), std::string::npos);
}

TEST(RenderMapSvgTest, EscapesTheTitle) {
  const std::string svg = RenderMapSvg(MakeLot(3), {}, {.title = "slots <38 & 39> \"run\""});
  EXPECT_NE(svg.find("slots &lt;38 &amp; 39&gt; &quot;run&quot;"), std::string::npos);
  EXPECT_EQ(svg.find("<38"), std::string::npos);
}

TEST(RenderMapSvgTest, LegendListsTrajectoryLabelsWithColors) {
  const std::string svg = RenderMapSvg(
      MakeLot(10), {{"truth", "#2ca02c", MakeDrive(0.0)}, {"estimate", "#d62728", MakeDrive(0.3)}});
  const std::string legend = GroupBody(svg, "legend");
  EXPECT_NE(legend.find(">truth</text>"), std::string::npos);
  EXPECT_NE(legend.find(">estimate</text>"), std::string::npos);
  EXPECT_NE(legend.find("stroke=\"#d62728\""), std::string::npos);
  EXPECT_NE(GroupBody(svg, "trajectories").find("stroke=\"#d62728\""), std::string::npos);
}

TEST(RenderMapSvgTest, DrawsTenMetreScaleBar) {
  EXPECT_NE(GroupBody(RenderMapSvg(MakeLot(3), {}), "scale_bar").find(">10 m<"), std::string::npos);
}

TEST(RenderMapSvgTest, EmptyMapWithTrajectory) {
  const std::string svg = RenderMapSvg(SemanticMap{}, {{"drive", "red", MakeDrive(0.0)}});
  EXPECT_TRUE(IsWellFormed(svg));
  EXPECT_NE(svg.find("<polyline"), std::string::npos);
}

TEST(RenderMapSvgTest, EmptyMapWithoutTrajectoryIsSmallAndValid) {
  const std::string svg = RenderMapSvg(SemanticMap{}, {});
  EXPECT_TRUE(IsWellFormed(svg));
  EXPECT_LT(svg.size(), 2000u);
}

TEST(RenderMapSvgTest, BigMapWithTwoLongDrivesStaysCompact) {
  const std::string svg = RenderMapSvg(MakeLot(120), {{"truth", "#2ca02c", MakeDrive(0.0)},
                                                      {"estimate", "#d62728", MakeDrive(0.3)}});
  EXPECT_TRUE(IsWellFormed(svg));
  EXPECT_LT(svg.size(), 400'000u);  // well under 1 MB
}

TEST(RenderMapSvgTest, RejectsNonPositiveScale) {
  EXPECT_THROW(RenderMapSvg(SemanticMap{}, {}, {.pixels_per_m = 0.0}), std::invalid_argument);
}

TEST(DecimatePolylineTest, KeepsAtMostMaxPointsWithBothEnds) {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < 60000; ++i) points.emplace_back(0.01 * i, 0.0);
  const std::vector<Eigen::Vector2d> out = DecimatePolyline(points, 0.0, 5000);
  EXPECT_EQ(out.size(), 5000u);
  EXPECT_EQ(out.front(), points.front());
  EXPECT_EQ(out.back(), points.back());
}

TEST(DecimatePolylineTest, DropsPointsCloserThanSpacing) {
  // Points 0.3 apart with a 0.5 spacing keep every second one, plus the end.
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i <= 10; ++i) points.emplace_back(0.3 * i, 0.0);
  const std::vector<Eigen::Vector2d> out = DecimatePolyline(points, 0.5, 5000);
  EXPECT_EQ(out.size(), 6u);  // 0, 0.6, 1.2, 1.8, 2.4, 3.0
  EXPECT_EQ(out.back(), points.back());
}

TEST(DecimatePolylineTest, ShortInputUnchanged) {
  const std::vector<Eigen::Vector2d> points{{0.0, 0.0}, {1.0, 1.0}};
  EXPECT_EQ(DecimatePolyline(points, 0.05, 5000), points);
}

}  // namespace
}  // namespace parkslam::viz

namespace parkslam::viz {
namespace {

TEST(RenderMapSvgLegendTest, UnlabeledTrajectoriesAreDrawnButNotListed) {
  Trajectory a{{0, SE2(0, 0, 0)}, {1, SE2(10, 0, 0)}};
  Trajectory b{{0, SE2(0, 1, 0)}, {1, SE2(10, 1, 0)}};
  const std::string svg = RenderMapSvg(SemanticMap{}, {{"runs", "#d62728", a}, {"", "#1f77b4", b}});
  EXPECT_NE(svg.find("#1f77b4"), std::string::npos);  // drawn
  const size_t legend = svg.find("id=\"legend\"");
  ASSERT_NE(legend, std::string::npos);
  const std::string legend_part = svg.substr(legend, svg.find("</g>", legend) - legend);
  EXPECT_NE(legend_part.find("runs"), std::string::npos);
  EXPECT_EQ(legend_part.find("#1f77b4"), std::string::npos);
}

}  // namespace
}  // namespace parkslam::viz
