#include "parkslam/io/map_json.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <functional>
#include <limits>

#include "parkslam/io/io_error.h"
#include "parkslam/io/test_util.h"

namespace parkslam::io {
namespace {

using testing::ErrorOf;
using ::testing::HasSubstr;
using testing::TempDir;

SemanticMap SampleMap() {
  SemanticMap map;
  map.metadata = {{"source", "simulator"}, {"world", "default"}, {"seed", "7"}};
  MapSlot a;
  a.id = "38";
  a.kind = SlotKind::kPerpendicular;
  a.corners_map = {Eigen::Vector2d(8.0, 5.6), Eigen::Vector2d(10.5, 5.6),
                   Eigen::Vector2d(10.5, 0.3), Eigen::Vector2d(8.0, 0.3)};
  MapSlot b;
  b.id = "t3";
  b.temporary = true;
  b.kind = SlotKind::kAngled;
  b.corners_map = {Eigen::Vector2d(-1.234, 2.5), Eigen::Vector2d(0.0, 2.5),
                   Eigen::Vector2d(2.0, 7.0), Eigen::Vector2d(-0.5, 7.0)};
  b.corner_observed = {true, true, false, true};
  b.corner_sigma_m = {0.05, 0.06, 0.25, 0.125};
  b.observation_count = 17;
  b.last_confirmed = "drive 2";
  MapSlot c;  // no painted ID, worn
  c.id = "";
  c.id_legible = false;
  c.kind = SlotKind::kParallel;
  c.corners_map = {Eigen::Vector2d(1, 1), Eigen::Vector2d(7, 1), Eigen::Vector2d(7, 3.5),
                   Eigen::Vector2d(1, 3.5)};
  MapSlot d = c;  // a second slot without ID is fine
  d.corners_map[0].x() = 0.999;
  map.slots = {a, b, c, d};
  map.obstacles = {{ObstacleKind::kPillar,
                    {Eigen::Vector2d(10.2, 0.0), Eigen::Vector2d(10.8, 0.0),
                     Eigen::Vector2d(10.8, 0.6), Eigen::Vector2d(10.2, 0.6)}},
                   {ObstacleKind::kWall, {Eigen::Vector2d(0, 0), Eigen::Vector2d(82, 0)}}};
  map.tags = {{7, Eigen::Vector2d(10.5, 0.3), 1.570796, 0.488, 0, {}},
              {12, Eigen::Vector2d(40.0, 0.01), -3.141593, 0.3, 1, "drive 2"},
              {13, Eigen::Vector2d(-20.0, 9.0), 0.0, 0.488, -1, {}}};
  return map;
}

void ExpectMapsEqual(const SemanticMap& a, const SemanticMap& b) {
  EXPECT_EQ(a.metadata, b.metadata);
  ASSERT_EQ(a.slots.size(), b.slots.size());
  for (std::size_t i = 0; i < a.slots.size(); ++i) {
    SCOPED_TRACE("slot " + std::to_string(i));
    EXPECT_EQ(a.slots[i].id, b.slots[i].id);
    EXPECT_EQ(a.slots[i].temporary, b.slots[i].temporary);
    EXPECT_EQ(a.slots[i].id_legible, b.slots[i].id_legible);
    EXPECT_EQ(a.slots[i].kind, b.slots[i].kind);
    for (int k = 0; k < kSlotCorners; ++k) {
      EXPECT_NEAR((a.slots[i].corners_map[k] - b.slots[i].corners_map[k]).norm(), 0, 1e-9);
      EXPECT_EQ(a.slots[i].corner_observed[k], b.slots[i].corner_observed[k]);
      EXPECT_NEAR(a.slots[i].corner_sigma_m[k], b.slots[i].corner_sigma_m[k], 1e-12);
    }
    EXPECT_EQ(a.slots[i].observation_count, b.slots[i].observation_count);
    EXPECT_EQ(a.slots[i].last_confirmed, b.slots[i].last_confirmed);
  }
  ASSERT_EQ(a.tags.size(), b.tags.size());
  for (std::size_t i = 0; i < a.tags.size(); ++i) {
    EXPECT_EQ(a.tags[i].tag_id, b.tags[i].tag_id);
    EXPECT_NEAR((a.tags[i].p_map - b.tags[i].p_map).norm(), 0, 1e-9);
    EXPECT_NEAR(a.tags[i].yaw_map_rad, b.tags[i].yaw_map_rad, 1e-12);
    EXPECT_NEAR(a.tags[i].size_m, b.tags[i].size_m, 1e-12);
    EXPECT_EQ(a.tags[i].obstacle_index, b.tags[i].obstacle_index);
    EXPECT_EQ(a.tags[i].last_confirmed, b.tags[i].last_confirmed);
  }
  ASSERT_EQ(a.obstacles.size(), b.obstacles.size());
  for (std::size_t i = 0; i < a.obstacles.size(); ++i) {
    EXPECT_EQ(a.obstacles[i].kind, b.obstacles[i].kind);
    ASSERT_EQ(a.obstacles[i].points_map.size(), b.obstacles[i].points_map.size());
    for (std::size_t k = 0; k < a.obstacles[i].points_map.size(); ++k) {
      EXPECT_NEAR((a.obstacles[i].points_map[k] - b.obstacles[i].points_map[k]).norm(), 0, 1e-9);
    }
  }
}

TEST(MapJsonTest, JsonRoundTripKeepsEveryField) {
  const SemanticMap map = SampleMap();
  ExpectMapsEqual(MapFromJson(MapToJson(map), "mem"), map);
}

TEST(MapJsonTest, WritesLastConfirmedOnlyWhereThereIsOne) {
  const nlohmann::json j = MapToJson(SampleMap());
  EXPECT_FALSE(j["slots"][0].contains("last_confirmed"));
  EXPECT_EQ(j["slots"][1]["last_confirmed"], "drive 2");
  EXPECT_FALSE(j["tags"][0].contains("last_confirmed"));
  EXPECT_EQ(j["tags"][1]["last_confirmed"], "drive 2");
  nlohmann::json bad = j;
  bad["tags"][1]["last_confirmed"] = 3;
  EXPECT_THROW(MapFromJson(bad, "mem"), IoError);
}

// Where the map's drive began: written only where there is one, read back
// to the rounding of the format, refused by field where it is malformed.
TEST(MapJsonTest, KeepsTheEntranceWhereThereIsOne) {
  SemanticMap map = SampleMap();
  EXPECT_FALSE(MapToJson(map).contains("entrance"));
  EXPECT_FALSE(MapFromJson(MapToJson(map), "mem").entrance.has_value());
  map.entrance = SE2(-8.0, 12.5, 0.0123);
  const nlohmann::json j = MapToJson(map);
  const SemanticMap read = MapFromJson(j, "mem");
  ASSERT_TRUE(read.entrance.has_value());
  EXPECT_NEAR((read.entrance->translation() - map.entrance->translation()).norm(), 0.0, 1e-9);
  EXPECT_NEAR(read.entrance->yaw(), 0.0123, 1e-9);
  nlohmann::json missing = j;
  missing["entrance"].erase("yaw");
  EXPECT_EQ(ErrorOf([&] { MapFromJson(missing, "map.json"); }),
            "map.json: entrance.yaw: missing key");
  nlohmann::json far = j;
  far["entrance"]["x"] = 1e9;
  EXPECT_THAT(ErrorOf([&] { MapFromJson(far, "map.json"); }), HasSubstr("entrance.x"));
}

TEST(MapJsonTest, FileRoundTripKeepsEveryField) {
  const TempDir dir;
  const SemanticMap map = SampleMap();
  WriteMap(dir / "map.json", map);
  ExpectMapsEqual(ReadMap(dir / "map.json"), map);
}

TEST(MapJsonTest, RoundsLengthsToMillimetresAndAnglesToMicroradians) {
  SemanticMap map;
  map.tags = {{1, Eigen::Vector2d(1.23449, -0.0004), 0.12345649, 0.4881, -1, {}}};
  const SemanticMap read = MapFromJson(MapToJson(map), "mem");
  EXPECT_DOUBLE_EQ(read.tags[0].p_map.x(), 1.234);
  EXPECT_DOUBLE_EQ(read.tags[0].p_map.y(), 0.0);
  EXPECT_DOUBLE_EQ(read.tags[0].yaw_map_rad, 0.123456);
  EXPECT_DOUBLE_EQ(read.tags[0].size_m, 0.488);
}

TEST(MapJsonTest, WritesHeaderFirstAndSmallArraysOnOneLine) {
  const TempDir dir;
  WriteMap(dir / "map.json", SampleMap());
  const std::string text = ReadTextFile(dir / "map.json");
  EXPECT_EQ(text.rfind("{\n  \"format\": \"parkslam-map\",\n  \"version\": 1,\n", 0), 0u)
      << text.substr(0, 200);
  EXPECT_THAT(text, HasSubstr("\"corners\": [[8.0, 5.6], [10.5, 5.6], [10.5, 0.3], [8.0, 0.3]]"));
  EXPECT_THAT(text, HasSubstr("{\"id\": 7, \"x\": 10.5, \"y\": 0.3, \"yaw\": 1.570796, "
                              "\"size_m\": 0.488, \"obstacle\": 0}"));
}

nlohmann::json SampleJson() { return MapToJson(SampleMap()); }

TEST(MapJsonTest, RejectsWrongFormat) {
  nlohmann::json j = SampleJson();
  j["format"] = "parkslam-dataset";
  EXPECT_EQ(ErrorOf([&] { MapFromJson(j, "map.json"); }),
            "map.json: format: expected 'parkslam-map', got 'parkslam-dataset'");
}

TEST(MapJsonTest, RejectsAnotherVersion) {
  nlohmann::json j = SampleJson();
  j["version"] = 2;
  EXPECT_EQ(ErrorOf([&] { MapFromJson(j, "map.json"); }),
            "map.json: version: unsupported version 2 (this build reads 1)");
}

TEST(MapJsonTest, RejectsAnUnknownKeyNamingItsPath) {
  nlohmann::json j = SampleJson();
  j["slots"][1]["colour"] = "white";
  EXPECT_EQ(ErrorOf([&] { MapFromJson(j, "map.json"); }), "map.json: slots[1].colour: unknown key");
}

TEST(MapJsonTest, RejectsAnUnknownTopLevelKey) {
  nlohmann::json j = SampleJson();
  j["extra"] = 1;
  EXPECT_EQ(ErrorOf([&] { MapFromJson(j, "map.json"); }), "map.json: extra: unknown key");
}

TEST(MapJsonTest, RejectsAMissingKey) {
  nlohmann::json j = SampleJson();
  j["tags"][2].erase("size_m");
  EXPECT_EQ(ErrorOf([&] { MapFromJson(j, "map.json"); }), "map.json: tags[2].size_m: missing key");
}

TEST(MapJsonTest, RejectsAWrongType) {
  nlohmann::json j = SampleJson();
  j["slots"][0]["id"] = 38;
  EXPECT_EQ(ErrorOf([&] { MapFromJson(j, "map.json"); }),
            "map.json: slots[0].id: expected a string, got an integer");
}

TEST(MapJsonTest, RejectsThreeCorners) {
  nlohmann::json j = SampleJson();
  j["slots"][3]["corners"].erase(3);
  EXPECT_EQ(ErrorOf([&] { MapFromJson(j, "map.json"); }),
            "map.json: slots[3].corners: expected 4 points, got 3");
}

TEST(MapJsonTest, RejectsANonFiniteNumber) {
  nlohmann::json j = SampleJson();
  j["obstacles"][1]["points"][1][0] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(ErrorOf([&] { MapFromJson(j, "map.json"); }),
            "map.json: obstacles[1].points[1][0]: not a finite number");
}

TEST(MapJsonTest, RejectsAnObstacleIndexOutOfRange) {
  nlohmann::json j = SampleJson();
  j["tags"][0]["obstacle"] = 2;  // two obstacles: 0 and 1
  EXPECT_THAT(ErrorOf([&] { MapFromJson(j, "map.json"); }),
              HasSubstr("map.json: tags[0].obstacle: index 2 out of range"));
  j["tags"][0]["obstacle"] = 1;
  EXPECT_NO_THROW(MapFromJson(j, "map.json"));
}

TEST(MapJsonTest, RejectsADuplicateSlotId) {
  nlohmann::json j = SampleJson();
  j["slots"][3]["id"] = "38";
  EXPECT_EQ(ErrorOf([&] { MapFromJson(j, "map.json"); }),
            "map.json: slots[3].id: duplicate id '38' (also slots[0])");
}

// Issue: "map JSON with duplicate tag IDs" was taken, and the localizer
// tied every sighting of the ID to one of the two.
TEST(MapJsonTest, RejectsADuplicateTagIdAndOneOutsideTheFamily) {
  nlohmann::json j = SampleJson();
  j["tags"][2]["id"] = 7;
  EXPECT_EQ(ErrorOf([&] { MapFromJson(j, "map.json"); }),
            "map.json: tags[2].id: duplicate id 7 (also tags[0])");
  j["tags"][2]["id"] = 587;
  EXPECT_EQ(ErrorOf([&] { MapFromJson(j, "map.json"); }),
            "map.json: tags[2].id: must be a tag36h11 ID in [0, 586], got 587");
}

// An independent probe: an ID of 100,000 digits and one of control characters.
TEST(MapJsonTest, RejectsAnIdTooLongOrWithControlCharacters) {
  nlohmann::json j = SampleJson();
  j["slots"][1]["id"] = std::string(100000, '9');
  EXPECT_EQ(ErrorOf([&] { MapFromJson(j, "map.json"); }),
            "map.json: slots[1].id: 100000 characters; an ID has at most 16");
  j["slots"][1]["id"] = std::string("\x01<script>");
  EXPECT_EQ(ErrorOf([&] { MapFromJson(j, "map.json"); }),
            "map.json: slots[1].id: holds a control character");
  j["slots"][1]["id"] = "B105";
  EXPECT_NO_THROW(MapFromJson(j, "map.json"));
}

TEST(MapJsonTest, RejectsASlotWithoutArea) {
  nlohmann::json j = SampleJson();
  j["slots"][0]["corners"][2] = j["slots"][0]["corners"][1];
  j["slots"][0]["corners"][3] = j["slots"][0]["corners"][0];
  EXPECT_THAT(ErrorOf([&] { MapFromJson(j, "map.json"); }),
              HasSubstr("map.json: slots[0].corners: the corners enclose 0.00 m^2, not a slot"));
}

TEST(MapJsonTest, RejectsAnUnknownSlotKind) {
  nlohmann::json j = SampleJson();
  j["slots"][0]["kind"] = "diagonal";
  EXPECT_THAT(ErrorOf([&] { MapFromJson(j, "map.json"); }),
              HasSubstr("map.json: slots[0].kind: expected perpendicular"));
}

// Values beyond the limits of common/plausible_ranges.h, named by path: a
// map with a corner at 1e308 once rendered to an SVG of infinities.
TEST(MapJsonTest, RejectsImplausibleValuesNamingTheirPath) {
  const auto error_with = [](const std::function<void(nlohmann::json&)>& edit) {
    nlohmann::json j = SampleJson();
    edit(j);
    return ErrorOf([&] { MapFromJson(j, "map.json"); });
  };
  EXPECT_EQ(error_with([](nlohmann::json& j) { j["slots"][0]["corners"][0][0] = 1e308; }),
            "map.json: slots[0].corners[0][0]: 1e+308 is beyond the plausible 100000 m");
  EXPECT_EQ(error_with([](nlohmann::json& j) { j["slots"][2]["corners"][3][1] = -100001.0; }),
            "map.json: slots[2].corners[3][1]: -100001 is beyond the plausible 100000 m");
  EXPECT_EQ(error_with([](nlohmann::json& j) { j["slots"][1]["corner_sigma_m"][2] = 11.0; }),
            "map.json: slots[1].corner_sigma_m[2]: 11 is outside the plausible range [0, 10] m");
  EXPECT_EQ(error_with([](nlohmann::json& j) { j["slots"][1]["corner_sigma_m"][0] = -0.5; }),
            "map.json: slots[1].corner_sigma_m[0]: -0.5 is outside the plausible range [0, 10] m");
  EXPECT_EQ(error_with([](nlohmann::json& j) { j["tags"][1]["x"] = 2e5; }),
            "map.json: tags[1].x: 2e+05 is beyond the plausible 100000 m");
  EXPECT_EQ(error_with([](nlohmann::json& j) { j["tags"][2]["y"] = -1e300; }),
            "map.json: tags[2].y: -1e+300 is beyond the plausible 100000 m");
  EXPECT_EQ(error_with([](nlohmann::json& j) { j["tags"][0]["yaw"] = 1e20; }),
            "map.json: tags[0].yaw: 1e+20 is beyond the plausible 10000 rad");
  EXPECT_EQ(error_with([](nlohmann::json& j) { j["tags"][0]["size_m"] = 6.0; }),
            "map.json: tags[0].size_m: 6 is beyond the plausible 5 m");
  EXPECT_EQ(error_with([](nlohmann::json& j) { j["obstacles"][1]["points"][1][0] = 1e6; }),
            "map.json: obstacles[1].points[1][0]: 1e+06 is beyond the plausible 100000 m");
  // At the limits themselves, still a map.
  EXPECT_EQ(error_with([](nlohmann::json& j) {
              j["slots"][0]["corners"][0][0] = -100000.0;
              j["slots"][1]["corner_sigma_m"][2] = 10.0;
              j["tags"][0]["yaw"] = 10000.0;
              j["tags"][0]["size_m"] = 5.0;
            }),
            "");
}

TEST(MapJsonTest, ReadingMalformedJsonNamesTheFile) {
  const TempDir dir;
  const auto file = dir.Write("map.json", "{\"format\": \"parkslam-map\", ");
  EXPECT_THAT(ErrorOf([&] { ReadMap(file); }), HasSubstr("map.json: invalid JSON"));
}

// The message of reading the sample map written to "map.json" with its first
// `from` replaced by `to`.
std::string ErrorReadingEdited(const std::string& from, const std::string& to) {
  const TempDir dir;
  WriteMap(dir / "map.json", SampleMap());
  std::string text = ReadTextFile(dir / "map.json");
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at == std::string::npos) return "";
  text.replace(at, from.size(), to);
  return ErrorOf([&] { ReadMap(dir.Write("map.json", text)); });
}

// nlohmann refuses a number beyond the range of a double with out_of_range,
// not parse_error, and names no position: the reader must still throw an
// IoError, and name the file and the field.
TEST(MapJsonTest, ReadingANumberTooLargeForADoubleNamesFileAndField) {
  const std::string yaw = ErrorReadingEdited("\"yaw\": 1.570796", "\"yaw\": 1e999");
  EXPECT_THAT(yaw, HasSubstr("map.json: tags[0].yaw: invalid JSON: "));
  EXPECT_THAT(yaw, HasSubstr("1e999"));
  EXPECT_THAT(ErrorReadingEdited("[10.5, 0.3], [8.0, 0.3]]", "[10.5, -1e999], [8.0, 0.3]]"),
              HasSubstr("map.json: slots[0].corners[2][1]: invalid JSON: "));
  EXPECT_THAT(ErrorReadingEdited("\"corner_sigma_m\": [0.05, 0.06, 0.25",
                                 "\"corner_sigma_m\": [0.05, 0.06, 2e308"),
              HasSubstr("map.json: slots[1].corner_sigma_m[2]: invalid JSON: "));
  // An integer field: 400 digits are read as a double, which overflows.
  const std::string huge_integer(400, '9');
  EXPECT_THAT(ErrorReadingEdited("\"obstacle\": 0}", "\"obstacle\": " + huge_integer + "}"),
              HasSubstr("map.json: tags[0].obstacle: invalid JSON: "));
  EXPECT_THAT(ErrorReadingEdited("\"version\": 1,", "\"version\": 1e999,"),
              HasSubstr("map.json: version: invalid JSON: "));
}

TEST(MapJsonTest, ReadingAMissingFileNamesIt) {
  const TempDir dir;
  EXPECT_THAT(ErrorOf([&] { ReadMap(dir / "none.json"); }), HasSubstr("none.json"));
}

TEST(MapJsonTest, WritingRefusesWhatWouldNotReadBack) {
  const TempDir dir;
  SemanticMap map = SampleMap();
  map.slots[1].id = "38";
  EXPECT_THAT(ErrorOf([&] { WriteMap(dir / "map.json", map); }), HasSubstr("duplicate id '38'"));
  map = SampleMap();
  map.slots[0].corners_map[2].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT(ErrorOf([&] { WriteMap(dir / "map.json", map); }),
              HasSubstr("slots[0].corners[2][1]: not a finite number"));
  EXPECT_FALSE(std::filesystem::exists(dir / "map.json"));
}

}  // namespace
}  // namespace parkslam::io
