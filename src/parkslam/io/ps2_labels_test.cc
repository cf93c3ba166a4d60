#include "parkslam/io/ps2_labels.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <string>
#include <utility>

#include "parkslam/common/angles.h"
#include "parkslam/io/io_error.h"
#include "parkslam/io/test_util.h"

namespace parkslam::io {
namespace {

using testing::ErrorOf;
using ::testing::HasSubstr;
using testing::TempDir;

// Two marks: a T at label (101, 51) whose separating line runs down the
// image (+y), an L at label (251.5, 51) labelled along its entrance, left
// (-x) towards the T, as DMPR-PS labels an L at the second end of a slot;
// one slot between them, written nested.
constexpr char kNested[] =
    R"({"marks": [[101, 51, 101, 200, 0], [251.5, 51, 150, 51, 1]],
        "slots": [[1, 2, 1, 90]]})";

TEST(Ps2LabelsTest, ReadsNestedListsZeroBased) {
  const TempDir dir;
  const Ps2Labels labels = ReadPs2Labels(dir.Write("a.json", kNested));
  ASSERT_EQ(labels.marking_points.size(), 2u);
  const Ps2MarkingPoint& t = labels.marking_points[0];
  EXPECT_NEAR((t.px - Eigen::Vector2d(100.5, 50.5)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(t.direction_rad, kPi / 2, 1e-12);  // down the image
  EXPECT_TRUE(t.is_t);
  const Ps2MarkingPoint& l = labels.marking_points[1];
  EXPECT_NEAR((l.px - Eigen::Vector2d(251.0, 50.5)).norm(), 0.0, 1e-12);
  // Read as its separating line: the T's, down the image.
  EXPECT_NEAR(l.direction_rad, kPi / 2, 1e-12);
  EXPECT_FALSE(l.is_t);
  ASSERT_EQ(labels.slots.size(), 1u);
  EXPECT_EQ(labels.slots[0].a, 0);
  EXPECT_EQ(labels.slots[0].b, 1);
}

TEST(Ps2LabelsTest, ReadsFlatSingleSlot) {
  const TempDir dir;
  const Ps2Labels labels = ReadPs2Labels(dir.Write(
      "a.json", R"({"marks": [[10, 10, 10, 60, 0], [160, 10, 160, 60, 0], [310, 10, 310, 60, 1]],
                    "slots": [3, 2, 1, 90]})"));
  ASSERT_EQ(labels.marking_points.size(), 3u);
  ASSERT_EQ(labels.slots.size(), 1u);
  EXPECT_EQ(labels.slots[0].a, 2);
  EXPECT_EQ(labels.slots[0].b, 1);
}

TEST(Ps2LabelsTest, ReadsFlatSingleMark) {
  const TempDir dir;
  const Ps2Labels labels =
      ReadPs2Labels(dir.Write("a.json", R"({"marks": [10.5, 20.5, 60.5, 20.5, 1], "slots": []})"));
  ASSERT_EQ(labels.marking_points.size(), 1u);
  EXPECT_NEAR((labels.marking_points[0].px - Eigen::Vector2d(10, 20)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(labels.marking_points[0].direction_rad, 0.0, 1e-12);
  EXPECT_FALSE(labels.marking_points[0].is_t);
  EXPECT_TRUE(labels.slots.empty());
}

TEST(Ps2LabelsTest, ReadsEmptyLists) {
  const TempDir dir;
  const Ps2Labels labels = ReadPs2Labels(dir.Write("a.json", R"({"marks": [], "slots": []})"));
  EXPECT_TRUE(labels.marking_points.empty());
  EXPECT_TRUE(labels.slots.empty());
}

// The message of reading `content` from a file "bad.json"; it must name the
// file.
std::string ErrorReading(const std::string& content) {
  const TempDir dir;
  const std::string message = ErrorOf([&] { ReadPs2Labels(dir.Write("bad.json", content)); });
  EXPECT_THAT(message, HasSubstr("bad.json: "));
  return message;
}

TEST(Ps2LabelsTest, AnLLabelledAlongItsEntranceWithoutASeparatingPartnerTurnsBy90Degrees) {
  // Both ends labelled along the entrance (no separating line to copy): the
  // L's other arm, +90 degrees from its label, is its separating line.
  const TempDir dir;
  const Ps2Labels labels =
      ReadPs2Labels(dir.Write("a.json", R"({"marks": [[101, 51, 200, 51, 1], [251, 51, 150, 51, 1]],
                    "slots": [[1, 2, 1, 90]]})"));
  ASSERT_EQ(labels.marking_points.size(), 2u);
  EXPECT_NEAR(labels.marking_points[0].direction_rad, kPi / 2, 1e-12);
  EXPECT_NEAR(labels.marking_points[1].direction_rad, -kPi / 2, 1e-12);
}

TEST(Ps2LabelsTest, AnLAlongItsSeparatingLineOrInNoSlotKeepsItsDirection) {
  // The L is the first end: its entrance leaves at +90 degrees from its
  // separating line (up the image, -y), so the label is that line. An
  // angled separating line 40 degrees from the entrance is not mistaken
  // for the entrance either.
  const TempDir dir;
  const Ps2Labels labels = ReadPs2Labels(
      dir.Write("a.json", R"({"marks": [[251, 151, 251, 51, 1], [101, 151, 101, 51, 0],
                              [401, 151, 324.4, 86.7, 1], [500, 500, 400, 500, 1]],
                    "slots": [[1, 2, 1, 90], [3, 1, 1, 40]]})"));
  ASSERT_EQ(labels.marking_points.size(), 4u);
  EXPECT_NEAR(labels.marking_points[0].direction_rad, -kPi / 2, 1e-12);
  EXPECT_NEAR(RadToDeg(labels.marking_points[2].direction_rad), -140.0, 0.1);
  EXPECT_NEAR(std::abs(labels.marking_points[3].direction_rad), kPi, 1e-12);
}

TEST(Ps2LabelsTest, WritesAnLAlongItsEntranceWhereDmprPsDoes) {
  // A slot from the T at x = 400 (first end: the entrance leaves it at +90
  // degrees from its separating line) to the L at x = 250; both separating
  // lines run down the image (+pi/2). The entrance leaves the L towards the
  // T, +x, at -90 degrees from its separating line, so the L is written
  // along the entrance, and read back as its separating line.
  Ps2Labels labels;
  labels.marking_points.push_back({Eigen::Vector2d(400.0, 50.0), kPi / 2, true});
  labels.marking_points.push_back({Eigen::Vector2d(250.0, 50.0), kPi / 2, false});
  labels.slots.push_back({0, 1, 1, 90.0});
  const nlohmann::json json = Ps2LabelsToJson(labels);
  EXPECT_NEAR(json["marks"][1][2].get<double>(), 250.5 + kPs2DirectionLengthPx, 1e-9);
  EXPECT_NEAR(json["marks"][1][3].get<double>(), 50.5, 1e-9);
  EXPECT_NEAR(json["marks"][0][3].get<double>(), 50.5 + kPs2DirectionLengthPx, 1e-9);
  const Ps2Labels back = Ps2LabelsFromJson(json, "written");
  ASSERT_EQ(back.marking_points.size(), 2u);
  EXPECT_NEAR(back.marking_points[1].direction_rad, kPi / 2, 1e-9);
  // Mirrored, the L at x = 400 and the T at 250: the entrance leaves the L
  // at +90 degrees, so it is written along its separating line.
  labels.marking_points[0].is_t = false;
  labels.marking_points[1].is_t = true;
  const nlohmann::json mirrored = Ps2LabelsToJson(labels);
  EXPECT_NEAR(mirrored["marks"][0][2].get<double>(), 400.5, 1e-9);
  EXPECT_NEAR(mirrored["marks"][0][3].get<double>(), 50.5 + kPs2DirectionLengthPx, 1e-9);
}

TEST(Ps2LabelsTest, WrittenLabelsReadBackToTheSamePointsAndSlots) {
  // An L at the second end, its separating line parallel to the T's, its
  // entrance leaving at a negative angle: written along the entrance.
  Ps2Labels labels;
  labels.marking_points.push_back({Eigen::Vector2d(10.25, 300.5), -2.0, true});
  labels.marking_points.push_back({Eigen::Vector2d(250.0, 0.0), -2.0, false});
  labels.slots.push_back({1, 0, 2, 60.0});
  const nlohmann::json json = Ps2LabelsToJson(labels);
  // 1-based in the file, as ps2.0's own labels.
  EXPECT_DOUBLE_EQ(json["marks"][0][0].get<double>(), 10.75);
  EXPECT_EQ(json["marks"][1][4].get<int>(), 1);
  // The L's arm point lies along the entrance, towards the T.
  EXPECT_LT(json["marks"][1][2].get<double>(), 250.5);
  EXPECT_GT(json["marks"][1][3].get<double>(), 0.5);
  EXPECT_EQ(json["slots"][0][0].get<int>(), 2);
  const Ps2Labels back = Ps2LabelsFromJson(json, "written");
  ASSERT_EQ(back.marking_points.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_NEAR((back.marking_points[i].px - labels.marking_points[i].px).norm(), 0.0, 1e-9);
    EXPECT_NEAR(
        AngleDiff(back.marking_points[i].direction_rad, labels.marking_points[i].direction_rad),
        0.0, 1e-9);
    EXPECT_EQ(back.marking_points[i].is_t, labels.marking_points[i].is_t);
  }
  ASSERT_EQ(back.slots.size(), 1u);
  EXPECT_EQ(back.slots[0].a, 1);
  EXPECT_EQ(back.slots[0].b, 0);
  // No marks, no slots: still lists.
  const nlohmann::json empty = Ps2LabelsToJson({});
  EXPECT_TRUE(empty["marks"].is_array());
  EXPECT_TRUE(Ps2LabelsFromJson(empty, "empty").marking_points.empty());
}

TEST(Ps2LabelsTest, RejectsWhatIsNotALabelObject) {
  EXPECT_THAT(ErrorReading(R"({"marks": [)"), HasSubstr("invalid JSON"));
  // Python's json.dump writes NaN as a bare word, which is not JSON.
  EXPECT_THAT(ErrorReading(R"({"marks": [[NaN, 1, 2, 3, 0]], "slots": []})"),
              HasSubstr("invalid JSON"));
  // A number too large for a double is refused by the parser, which does not
  // say where: the message names the field.
  EXPECT_THAT(ErrorReading(R"({"marks": [[1e999, 2, 3, 4, 0]], "slots": []})"),
              HasSubstr("bad.json: marks[0][0]: invalid JSON"));
  EXPECT_THAT(ErrorReading(R"({"marks": [[1, 2, 3, 4, 0]], "slots": [[1, 1, 1, -1e999]]})"),
              HasSubstr("bad.json: slots[0][3]: invalid JSON"));
  EXPECT_THAT(ErrorReading(R"([1, 2])"), HasSubstr("expected an object"));
  EXPECT_THAT(ErrorReading(R"({"marks": []})"), HasSubstr("slots: missing key"));
  EXPECT_THAT(ErrorReading(R"({"marks": [], "slots": [], "extra": 1})"),
              HasSubstr("extra: unknown key"));
  EXPECT_THAT(ErrorReading(R"({"marks": 5, "slots": []})"),
              HasSubstr("marks: expected an array, got an integer"));
}

TEST(Ps2LabelsTest, RejectsMalformedMarks) {
  EXPECT_THAT(ErrorReading(R"({"marks": [[1, 2, 3, 4]], "slots": []})"),
              HasSubstr("marks[0]: expected 5 numbers [x, y, dx, dy, shape], got 4"));
  EXPECT_THAT(ErrorReading(R"({"marks": [[1, 2, 3, 4, 0], [1, 2, "3", 4, 0]], "slots": []})"),
              HasSubstr("marks[1][2]: expected a number, got a string"));
  EXPECT_THAT(ErrorReading(R"({"marks": [[1, 2, 3, 4, 0], [1, 2, null, 4, 0]], "slots": []})"),
              HasSubstr("marks[1][2]: expected a number, got null"));
  EXPECT_THAT(ErrorReading(R"({"marks": [[1, 2, 3, 4, 2]], "slots": []})"),
              HasSubstr("marks[0][4]: expected 0 (T) or 1 (L), got 2"));
  EXPECT_THAT(ErrorReading(R"({"marks": [[1, 2, 1, 2, 0]], "slots": []})"),
              HasSubstr("marks[0]: the separating-line point"));
  // Nested, with a stray number: not taken for the flat form.
  EXPECT_THAT(ErrorReading(R"({"marks": [[1, 2, 3, 4, 0], 5], "slots": []})"),
              HasSubstr("marks[1]: expected an array, got an integer"));
  // Flat single mark: the fields are named marks[k].
  EXPECT_THAT(ErrorReading(R"({"marks": [1, 2, 3, 4, 0.5], "slots": []})"),
              HasSubstr("marks[4]: expected 0 (T) or 1 (L)"));
  EXPECT_THAT(ErrorReading(R"({"marks": [1, 2, 3, 4, 0, 7], "slots": []})"),
              HasSubstr("marks: expected 5 numbers"));
}

TEST(Ps2LabelsTest, RejectsMalformedSlots) {
  const std::string marks = R"({"marks": [[1, 2, 3, 4, 0], [101, 2, 103, 4, 0]], "slots": )";
  EXPECT_THAT(ErrorReading(marks + "[[1, 2, 1]]}"),
              HasSubstr("slots[0]: expected 4 numbers [i, j, type, angle], got 3"));
  EXPECT_THAT(ErrorReading(marks + "[[1, 2, 1, 90], [0, 1, 1, 90]]}"),
              HasSubstr("slots[1][0]: expected a 1-based index into marks (1 to 2), got 0"));
  EXPECT_THAT(ErrorReading(marks + "[[1, 3, 1, 90]]}"),
              HasSubstr("slots[0][1]: expected a 1-based index into marks (1 to 2), got 3"));
  EXPECT_THAT(ErrorReading(marks + "[[1.5, 2, 1, 90]]}"),
              HasSubstr("slots[0][0]: expected a 1-based index"));
  EXPECT_THAT(ErrorReading(marks + "[[1, 2, \"x\", 90]]}"),
              HasSubstr("slots[0][2]: expected a number"));
  EXPECT_THAT(ErrorReading(marks + "[[2, 2, 1, 90]]}"),
              HasSubstr("slots[0]: both ends of the entrance are mark 2"));
  // Flat single slot.
  EXPECT_THAT(ErrorReading(marks + "[1, 5, 1, 90]}"),
              HasSubstr("slots[1]: expected a 1-based index into marks (1 to 2), got 5"));
  // A slot with no marks to point at.
  EXPECT_THAT(ErrorReading(R"({"marks": [], "slots": [1, 2, 1, 90]})"),
              HasSubstr("slots[0]: expected a 1-based index into marks (1 to 0)"));
}

TEST(Ps2LabelsTest, RejectsNonFiniteNumbers) {
  // Not expressible in JSON text, but a parsed document can hold them.
  nlohmann::json json = nlohmann::json::parse(kNested);
  json["marks"][1][3] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT(ErrorOf([&] { Ps2LabelsFromJson(json, "doc.json"); }),
              HasSubstr("doc.json: marks[1][3]: not a finite number"));
  json = nlohmann::json::parse(kNested);
  json["slots"][0][3] = std::numeric_limits<double>::infinity();
  EXPECT_THAT(ErrorOf([&] { Ps2LabelsFromJson(json, "doc.json"); }),
              HasSubstr("doc.json: slots[0][3]: not a finite number"));
}

// Pixels beyond kMaxPixelCoordinate_px and slot angles beyond kMaxAngle_deg
// (common/plausible_ranges.h); a mark may still lie off its image.
TEST(Ps2LabelsTest, RejectsImplausiblePixelsAndAngles) {
  EXPECT_THAT(ErrorReading(R"({"marks": [[1, 2, 3, 4, 0], [1e308, 2, 3, 4, 0]], "slots": []})"),
              HasSubstr(": marks[1][0]: 1e+308 is beyond the plausible 32768 px"));
  EXPECT_THAT(ErrorReading(R"({"marks": [[1, 2, 3, -40000, 0]], "slots": []})"),
              HasSubstr(": marks[0][3]: -40000 is beyond the plausible 32768 px"));
  const std::string marks = R"({"marks": [[1, 2, 3, 4, 0], [101, 2, 103, 4, 0]], "slots": )";
  EXPECT_THAT(ErrorReading(marks + "[[1, 2, 1, 1e9]]}"),
              HasSubstr(": slots[0][3]: 1e+09 is beyond the plausible 360 deg"));
  const TempDir dir;
  EXPECT_NO_THROW(ReadPs2Labels(
      dir.Write("off.json", R"({"marks": [[-20, 610.5, 30, 640, 1]], "slots": []})")));
}

TEST(Ps2LabelsTest, MissingFileIsNamed) {
  const TempDir dir;
  const std::string message = ErrorOf([&] { ReadPs2Labels(dir / "absent.json"); });
  EXPECT_THAT(message, HasSubstr("absent.json"));
}

TEST(ListPs2ImagesTest, ListsLabelledJpegsSorted) {
  const TempDir dir;
  for (const char* name : {"b.jpg", "b.json", "a.jpg", "a.json", "unlabelled.jpg",
                           "label_only.json", "other.png", "other.json"}) {
    dir.Write(name, "x");
  }
  EXPECT_EQ(ListPs2Images(dir.path()), (std::vector<std::string>{"a", "b"}));
  EXPECT_THAT(ErrorOf([&] { ListPs2Images(dir / "absent"); }), HasSubstr("cannot list the folder"));
  // A labelled view whose image or labels is no plain file is refused, named,
  // not left out of the score.
  std::filesystem::create_directories(dir / "folder.jpg");
  dir.Write("folder.json", "x");
  EXPECT_THAT(ErrorOf([&] { ListPs2Images(dir.path()); }),
              HasSubstr("folder.jpg: not a plain file"));
  std::filesystem::remove(dir / "folder.jpg");
  std::filesystem::create_directories(dir / "c.json");
  dir.Write("c.jpg", "x");
  EXPECT_THAT(ErrorOf([&] { ListPs2Images(dir.path()); }), HasSubstr("c.json: not a plain file"));
}

// The 20 labelled images of the real ps2.0 sample (shared/data).
std::filesystem::path SampleDir() {
  const char* root = std::getenv("PARKSLAM_SHARED_DATA");
  return std::filesystem::path(root != nullptr ? root : "../shared/data") / "ps2.0-sample";
}

TEST(Ps2LabelsSampleTest, ReadsAllRealLabels) {
  if (!std::filesystem::is_directory(SampleDir())) {
    GTEST_SKIP() << "real data not found at " << SampleDir() << " (shared/data absent)";
  }
  const std::vector<std::string> names = ListPs2Images(SampleDir());
  ASSERT_EQ(names.size(), 20u);
  int marks = 0, t_marks = 0, slots = 0;
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    const Ps2Labels labels = ReadPs2Labels(SampleDir() / (name + ".json"));
    EXPECT_FALSE(labels.marking_points.empty());
    EXPECT_FALSE(labels.slots.empty());
    marks += static_cast<int>(labels.marking_points.size());
    slots += static_cast<int>(labels.slots.size());
    for (const Ps2MarkingPoint& mark : labels.marking_points) {
      if (mark.is_t) ++t_marks;
      // Inside the image: pixel centres 0 to 599, pixel edges half a pixel
      // beyond.
      EXPECT_GE(mark.px.minCoeff(), -0.5);
      EXPECT_LE(mark.px.maxCoeff(), kPs2ImageSizePx - 0.5);
      EXPECT_TRUE(std::isfinite(mark.direction_rad));
    }
    // Entrance lines between 2 m (120 px) and 7 m (420 px): perpendicular to
    // parallel slots at 60 px per metre.
    for (const Ps2Slot& slot : labels.slots) {
      const double length_px = (labels.marking_points[static_cast<std::size_t>(slot.a)].px -
                                labels.marking_points[static_cast<std::size_t>(slot.b)].px)
                                   .norm();
      EXPECT_GT(length_px, 120.0);
      EXPECT_LT(length_px, 420.0);
    }
  }
  // Every L of the sample ends a perpendicular slot; read as separating
  // lines, each leaves its entrance within 5 degrees of square, and parallel
  // to its partner's within 5 degrees (7 of the 11 are labelled along the
  // entrance, as DMPR-PS labels an L at a slot's second end).
  int l_ends = 0;
  for (const std::string& name : names) {
    const Ps2Labels labels = ReadPs2Labels(SampleDir() / (name + ".json"));
    for (const Ps2Slot& slot : labels.slots) {
      for (const auto& [m, o] : {std::pair{slot.a, slot.b}, std::pair{slot.b, slot.a}}) {
        const Ps2MarkingPoint& mark = labels.marking_points[static_cast<std::size_t>(m)];
        const Ps2MarkingPoint& other = labels.marking_points[static_cast<std::size_t>(o)];
        if (mark.is_t) continue;
        ++l_ends;
        const Eigen::Vector2d entrance = other.px - mark.px;
        const double off_square = std::abs(
            std::abs(AngleDiff(std::atan2(entrance.y(), entrance.x()), mark.direction_rad)) -
            kPi / 2);
        EXPECT_LT(RadToDeg(off_square), 5.0) << name;
        EXPECT_LT(RadToDeg(std::abs(AngleDiff(mark.direction_rad, other.direction_rad))), 5.0)
            << name;
      }
    }
  }
  EXPECT_EQ(l_ends, 11);
  // Counted independently, with Python's json module.
  EXPECT_EQ(marks, 50);
  EXPECT_EQ(t_marks, 39);
  EXPECT_EQ(slots, 28);

  // One value checked by hand: the first mark of 20160725-3-1 is labelled
  // (240.478, 57.813) with its line through (87.008, 49.488).
  const Ps2Labels first = ReadPs2Labels(SampleDir() / "20160725-3-1.json");
  ASSERT_FALSE(first.marking_points.empty());
  EXPECT_NEAR(first.marking_points[0].px.x(), 239.978, 1e-3);
  EXPECT_NEAR(first.marking_points[0].px.y(), 57.313, 1e-3);
  EXPECT_NEAR(RadToDeg(first.marking_points[0].direction_rad), -176.895, 1e-3);
  EXPECT_TRUE(first.marking_points[0].is_t);
}

}  // namespace
}  // namespace parkslam::io
