#include "parkslam/eval/detection_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "parkslam/common/angles.h"

namespace parkslam::eval {
namespace {

constexpr double kPixelsPerM = 60.0;  // ps2.0: 600 px for 10 m

LabelledMarkingPoint Point(double x, double y, double direction_deg, bool is_t = true) {
  return {Eigen::Vector2d(x, y), DegToRad(direction_deg), is_t};
}

// A detection of `truth` shifted by distance_px along x and turned by
// turn_deg.
LabelledMarkingPoint Shifted(const LabelledMarkingPoint& truth, double distance_px,
                             double turn_deg) {
  LabelledMarkingPoint p = truth;
  p.px.x() += distance_px;
  p.direction_rad += DegToRad(turn_deg);
  return p;
}

EntranceLine Line(double ax, double ay, double bx, double by) {
  return {Eigen::Vector2d(ax, ay), Eigen::Vector2d(bx, by)};
}

// A perpendicular slot 150 px wide and 318 px deep (2.5 x 5.3 m), entrance
// from corner 0 at (x0, y0) to corner 1 at (x0 + 150, y0), lying below it.
SlotCornersPx Corners(double x0, double y0) {
  return {Eigen::Vector2d(x0, y0), Eigen::Vector2d(x0 + 150, y0),
          Eigen::Vector2d(x0 + 150, y0 + 318), Eigen::Vector2d(x0, y0 + 318)};
}

TEST(DirectionDifferenceTest, WrapsAroundTheCircle) {
  EXPECT_NEAR(RadToDeg(DirectionDifferenceRad(DegToRad(359), DegToRad(1))), 2.0, 1e-9);
  EXPECT_NEAR(RadToDeg(DirectionDifferenceRad(DegToRad(1), DegToRad(359))), 2.0, 1e-9);
  EXPECT_NEAR(RadToDeg(DirectionDifferenceRad(DegToRad(-179), DegToRad(179))), 2.0, 1e-9);
  EXPECT_NEAR(RadToDeg(DirectionDifferenceRad(DegToRad(0), DegToRad(180))), 180.0, 1e-9);
  EXPECT_NEAR(RadToDeg(DirectionDifferenceRad(DegToRad(730), DegToRad(10))), 0.0, 1e-9);
  EXPECT_NEAR(RadToDeg(DirectionDifferenceRad(DegToRad(30), DegToRad(-60))), 90.0, 1e-9);
}

TEST(MarkingPointsMatchTest, ExactHitMatches) {
  const LabelledMarkingPoint truth = Point(300, 200, 90);
  EXPECT_TRUE(MarkingPointsMatch(truth, truth));
}

TEST(MarkingPointsMatchTest, DistanceThresholdIsTenPixels) {
  const LabelledMarkingPoint truth = Point(300, 200, 90);
  EXPECT_TRUE(MarkingPointsMatch(Shifted(truth, 9.9, 0), truth));
  EXPECT_TRUE(MarkingPointsMatch(Shifted(truth, -9.9, 0), truth));
  EXPECT_FALSE(MarkingPointsMatch(Shifted(truth, 10.1, 0), truth));
  // Diagonal: (7, 7) px is 9.90 px away, (7.2, 7.2) px 10.18 px.
  LabelledMarkingPoint diagonal = truth;
  diagonal.px += Eigen::Vector2d(7.0, 7.0);
  EXPECT_TRUE(MarkingPointsMatch(diagonal, truth));
  diagonal.px = truth.px + Eigen::Vector2d(7.2, 7.2);
  EXPECT_FALSE(MarkingPointsMatch(diagonal, truth));
}

TEST(MarkingPointsMatchTest, DirectionThresholdIsThirtyDegrees) {
  const LabelledMarkingPoint truth = Point(300, 200, 90);
  EXPECT_TRUE(MarkingPointsMatch(Shifted(truth, 0, 29), truth));
  EXPECT_TRUE(MarkingPointsMatch(Shifted(truth, 0, -29), truth));
  EXPECT_FALSE(MarkingPointsMatch(Shifted(truth, 0, 31), truth));
  EXPECT_FALSE(MarkingPointsMatch(Shifted(truth, 0, -31), truth));
  // Pointing the opposite way is no match, however close.
  EXPECT_FALSE(MarkingPointsMatch(Shifted(truth, 0, 180), truth));
}

TEST(MarkingPointsMatchTest, DirectionWrapsAroundTheCircle) {
  EXPECT_TRUE(MarkingPointsMatch(Point(300, 200, 359), Point(300, 200, 1)));
  EXPECT_TRUE(MarkingPointsMatch(Point(300, 200, -175), Point(300, 200, 175)));
  EXPECT_FALSE(MarkingPointsMatch(Point(300, 200, -145), Point(300, 200, 170)));
}

TEST(MarkingPointsMatchTest, ShapeComparedOnlyWhenAsked) {
  const LabelledMarkingPoint t_point = Point(300, 200, 90, true);
  const LabelledMarkingPoint l_point = Point(300, 200, 90, false);
  EXPECT_TRUE(MarkingPointsMatch(l_point, t_point));  // DMPR-PS ignores the shape
  DetectionMatchOptions options;
  options.require_same_shape = true;
  EXPECT_FALSE(MarkingPointsMatch(l_point, t_point, options));
  EXPECT_TRUE(MarkingPointsMatch(t_point, t_point, options));
}

TEST(MarkingPointsMatchTest, NonFiniteNeverMatches) {
  const LabelledMarkingPoint truth = Point(300, 200, 90);
  LabelledMarkingPoint bad = truth;
  bad.px.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(MarkingPointsMatch(bad, truth));
  bad = truth;
  bad.direction_rad = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(MarkingPointsMatch(bad, truth));
}

TEST(MatchMarkingPointsTest, CountsHitsMissesAndFalseAlarms) {
  const std::vector<LabelledMarkingPoint> truth = {Point(100, 100, 90), Point(250, 100, 90),
                                                   Point(400, 100, 90)};
  const std::vector<LabelledMarkingPoint> detected = {
      Shifted(truth[2], 3, 5),      // hit
      Shifted(truth[0], 12, 0),     // too far: false positive, truth[0] missed
      Point(500, 500, 0),           // nothing there
      Shifted(truth[1], -1, -10)};  // hit
  const DetectionMatch match = MatchMarkingPoints(detected, truth);
  EXPECT_EQ(match.true_positives(), 2);
  EXPECT_EQ(match.false_positives(), 2);
  EXPECT_EQ(match.false_negatives(), 1);
  EXPECT_EQ(match.truth_of_detected, (std::vector<int>{2, -1, -1, 1}));
  EXPECT_EQ(match.detected_of_truth, (std::vector<int>{-1, 3, 0}));
}

TEST(MatchMarkingPointsTest, DuplicateDetectionIsFalsePositive) {
  const std::vector<LabelledMarkingPoint> truth = {Point(100, 100, 90)};
  // The farther one comes first: the nearer must still win.
  const std::vector<LabelledMarkingPoint> detected = {Shifted(truth[0], 6, 0),
                                                      Shifted(truth[0], -2, 0)};
  const DetectionMatch match = MatchMarkingPoints(detected, truth);
  ASSERT_EQ(match.pairs.size(), 1u);
  EXPECT_EQ(match.pairs[0].detected, 1);
  EXPECT_NEAR(match.pairs[0].distance_px, 2.0, 1e-12);
  EXPECT_EQ(match.false_positives(), 1);
  EXPECT_EQ(match.false_negatives(), 0);
  DetectionCounts counts;
  counts.Add(match);
  EXPECT_DOUBLE_EQ(counts.precision(), 0.5);
  EXPECT_DOUBLE_EQ(counts.recall(), 1.0);
}

TEST(MatchMarkingPointsTest, OneDetectionMatchesOneLabelOnly) {
  // Two labels 12 px apart, one detection between them.
  const std::vector<LabelledMarkingPoint> truth = {Point(100, 100, 90), Point(112, 100, 90)};
  const std::vector<LabelledMarkingPoint> detected = {Point(107, 100, 90)};
  const DetectionMatch match = MatchMarkingPoints(detected, truth);
  EXPECT_EQ(match.true_positives(), 1);
  EXPECT_EQ(match.false_negatives(), 1);
  EXPECT_EQ(match.truth_of_detected[0], 1);  // the nearer label
}

TEST(MatchMarkingPointsTest, EmptyInputs) {
  const std::vector<LabelledMarkingPoint> none;
  const std::vector<LabelledMarkingPoint> two = {Point(100, 100, 90), Point(300, 100, 90)};

  DetectionCounts nothing;
  nothing.Add(MatchMarkingPoints(none, none));
  EXPECT_EQ(nothing.true_positives + nothing.false_positives + nothing.false_negatives, 0);
  EXPECT_DOUBLE_EQ(nothing.precision(), 1.0);
  EXPECT_DOUBLE_EQ(nothing.recall(), 1.0);

  DetectionCounts blind;
  blind.Add(MatchMarkingPoints(none, two));
  EXPECT_EQ(blind.false_negatives, 2);
  EXPECT_DOUBLE_EQ(blind.precision(), 1.0);  // nothing claimed, nothing wrong
  EXPECT_DOUBLE_EQ(blind.recall(), 0.0);

  DetectionCounts dreaming;
  dreaming.Add(MatchMarkingPoints(two, none));
  EXPECT_EQ(dreaming.false_positives, 2);
  EXPECT_DOUBLE_EQ(dreaming.precision(), 0.0);
  EXPECT_DOUBLE_EQ(dreaming.recall(), 1.0);
}

TEST(MatchMarkingPointsTest, RejectsInvalidOptions) {
  DetectionMatchOptions options;
  options.max_distance_px = 0.0;
  std::string error;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("max_distance_px"), std::string::npos);
  EXPECT_THROW(MatchMarkingPoints({}, {}, options), std::invalid_argument);
  options = {};
  options.max_direction_difference_rad = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("max_direction_difference_rad"), std::string::npos);
  EXPECT_THROW(MatchSlots({}, {}, options), std::invalid_argument);
  EXPECT_TRUE(DetectionMatchOptions{}.IsValid(nullptr));
}

TEST(DetectionCountsTest, SumsOverImages) {
  const std::vector<LabelledMarkingPoint> truth = {Point(100, 100, 90), Point(300, 100, 90)};
  DetectionCounts counts;
  counts.Add(MatchMarkingPoints({truth[0]}, truth));            // 1 TP, 1 FN
  counts.Add(MatchMarkingPoints(truth, truth));                 // 2 TP
  counts.Add(MatchMarkingPoints({Point(500, 500, 0)}, truth));  // 1 FP, 2 FN
  EXPECT_EQ(counts.true_positives, 3);
  EXPECT_EQ(counts.false_positives, 1);
  EXPECT_EQ(counts.false_negatives, 3);
  EXPECT_DOUBLE_EQ(counts.precision(), 0.75);
  EXPECT_DOUBLE_EQ(counts.recall(), 0.5);
  DetectionCounts twice = counts;
  twice.Add(counts);
  EXPECT_EQ(twice.true_positives, 6);
  EXPECT_DOUBLE_EQ(twice.precision(), 0.75);
}

TEST(EntranceLinesOfTest, LooksUpTheMarkingPoints) {
  const std::vector<LabelledMarkingPoint> points = {Point(1, 2, 0), Point(3, 4, 0), Point(5, 6, 0)};
  const std::vector<EntranceLine> lines = EntranceLinesOf(points, {{2, 0}, {0, 1}});
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].a_px, Eigen::Vector2d(5, 6));
  EXPECT_EQ(lines[0].b_px, Eigen::Vector2d(1, 2));
  EXPECT_EQ(lines[1].b_px, Eigen::Vector2d(3, 4));
  EXPECT_THROW(EntranceLinesOf(points, {{0, 3}}), std::invalid_argument);
  EXPECT_THROW(EntranceLinesOf(points, {{-1, 0}}), std::invalid_argument);
}

TEST(EntranceLinesMatchTest, BothEndsWithinTenPixels) {
  const EntranceLine truth = Line(100, 100, 250, 100);
  EXPECT_TRUE(EntranceLinesMatch(truth, truth));
  EXPECT_TRUE(EntranceLinesMatch(Line(109.9, 100, 250, 90.1), truth));
  EXPECT_FALSE(EntranceLinesMatch(Line(110.1, 100, 250, 100), truth));
  EXPECT_FALSE(EntranceLinesMatch(Line(100, 100, 250, 110.1), truth));
}

TEST(EntranceLinesMatchTest, EitherOrderAndReportsTheSwap) {
  const EntranceLine truth = Line(100, 100, 250, 100);
  bool swapped = true;
  EXPECT_TRUE(EntranceLinesMatch(Line(101, 100, 249, 100), truth, {}, &swapped));
  EXPECT_FALSE(swapped);
  EXPECT_TRUE(EntranceLinesMatch(Line(249, 100, 101, 100), truth, {}, &swapped));
  EXPECT_TRUE(swapped);
  EXPECT_FALSE(EntranceLinesMatch(Line(260.1, 100, 101, 100), truth, {}, &swapped));
}

TEST(MatchSlotsTest, CountsAndDuplicates) {
  const std::vector<EntranceLine> truth = {Line(100, 100, 250, 100), Line(250, 100, 400, 100),
                                           Line(400, 100, 550, 100)};
  const std::vector<EntranceLine> detected = {
      Line(402, 100, 253, 100),   // truth[1], swapped
      Line(103, 100, 251, 100),   // truth[0]
      Line(100, 100, 251, 100),   // truth[0] again, nearer: wins
      Line(100, 100, 400, 100)};  // spans two slots: matches nothing
  const DetectionMatch match = MatchSlots(detected, truth);
  EXPECT_EQ(match.truth_of_detected, (std::vector<int>{1, -1, 0, -1}));
  EXPECT_EQ(match.detected_of_truth, (std::vector<int>{2, 0, -1}));
  EXPECT_EQ(match.false_positives(), 2);
  EXPECT_EQ(match.false_negatives(), 1);
  for (const DetectionPair& pair : match.pairs) {
    EXPECT_EQ(pair.swapped, pair.detected == 0);
    EXPECT_NEAR(pair.distance_px, pair.detected == 0 ? 3.0 : 1.0, 1e-12);
  }
}

TEST(MatchSlotsTest, EmptyInputs) {
  const std::vector<EntranceLine> one = {Line(100, 100, 250, 100)};
  DetectionCounts counts;
  counts.Add(MatchSlots({}, {}));
  counts.Add(MatchSlots({}, one));
  EXPECT_EQ(counts.false_negatives, 1);
  EXPECT_EQ(counts.false_positives, 0);
  EXPECT_DOUBLE_EQ(counts.precision(), 1.0);
  EXPECT_DOUBLE_EQ(counts.recall(), 0.0);
}

TEST(SlotCornerErrorsTest, MetresOverMatchedSlots) {
  const std::vector<SlotCornersPx> truth = {Corners(100, 100), Corners(250, 100)};
  SlotCornersPx off = Corners(100, 100);
  off[0].x() += 3.0;                                                     // 0.05 m
  off[2].y() += 12.0;                                                    // 0.2 m
  const std::vector<SlotCornersPx> detected = {off, Corners(400, 400)};  // second: spurious
  const DetectionMatch match =
      MatchSlots({{detected[0][0], detected[0][1]}, {detected[1][0], detected[1][1]}},
                 {{truth[0][0], truth[0][1]}, {truth[1][0], truth[1][1]}});
  ASSERT_EQ(match.true_positives(), 1);
  SlotCornerErrors errors;
  AddSlotCornerErrors(match, detected, truth, kPixelsPerM, &errors);
  EXPECT_EQ(errors.entrance_m.count, 2);
  EXPECT_NEAR(errors.entrance_m.mean(), 0.025, 1e-12);
  EXPECT_NEAR(errors.entrance_m.max, 0.05, 1e-12);
  EXPECT_EQ(errors.all_corners_m.count, 4);
  EXPECT_NEAR(errors.all_corners_m.mean(), 0.0625, 1e-12);
  EXPECT_NEAR(errors.all_corners_m.rms(), std::sqrt((0.05 * 0.05 + 0.2 * 0.2) / 4), 1e-12);
  EXPECT_NEAR(errors.all_corners_m.max, 0.2, 1e-12);
}

TEST(SlotCornerErrorsTest, SwappedEntranceComparesCorrespondingCorners) {
  const SlotCornersPx truth = Corners(100, 100);
  // The same slot seen from its other end: corners 1, 0, 3, 2 of the truth.
  const SlotCornersPx detected = {truth[1], truth[0], truth[3], truth[2]};
  const DetectionMatch match = MatchSlots({{detected[0], detected[1]}}, {{truth[0], truth[1]}});
  ASSERT_EQ(match.true_positives(), 1);
  EXPECT_TRUE(match.pairs[0].swapped);
  SlotCornerErrors errors;
  AddSlotCornerErrors(match, {detected}, {truth}, kPixelsPerM, &errors);
  EXPECT_EQ(errors.all_corners_m.count, 4);
  EXPECT_NEAR(errors.all_corners_m.max, 0.0, 1e-12);
}

TEST(SlotCornerErrorsTest, EmptyIsZeroAndBadInputThrows) {
  SlotCornerErrors errors;
  EXPECT_EQ(errors.all_corners_m.mean(), 0.0);
  EXPECT_EQ(errors.all_corners_m.rms(), 0.0);
  const DetectionMatch match = MatchSlots({Line(0, 0, 150, 0)}, {Line(0, 0, 150, 0)});
  EXPECT_THROW(AddSlotCornerErrors(match, {}, {Corners(0, 0)}, kPixelsPerM, &errors),
               std::invalid_argument);
  EXPECT_THROW(AddSlotCornerErrors(match, {Corners(0, 0)}, {Corners(0, 0)}, 0.0, &errors),
               std::invalid_argument);
  AddSlotCornerErrors(match, {Corners(0, 0)}, {Corners(0, 0)}, kPixelsPerM, &errors);
  EXPECT_EQ(errors.all_corners_m.count, 4);
}

TEST(ErrorAccumulatorTest, MeanRmsMaxAndMerge) {
  ErrorAccumulator a, b;
  a.Add(3.0);
  a.Add(4.0);
  b.Add(0.0);
  b.Add(5.0);
  EXPECT_DOUBLE_EQ(a.mean(), 3.5);
  EXPECT_DOUBLE_EQ(a.rms(), std::sqrt(12.5));
  a.Add(b);
  EXPECT_EQ(a.count, 4);
  EXPECT_DOUBLE_EQ(a.mean(), 3.0);
  EXPECT_DOUBLE_EQ(a.rms(), std::sqrt(50.0 / 4));
  EXPECT_DOUBLE_EQ(a.max, 5.0);
}

TEST(IdCountsTest, OnlyTheFullIdIsRight) {
  // Eight slots side by side, each detected exactly.
  std::vector<EntranceLine> lines;
  for (int i = 0; i < 8; ++i) lines.push_back(Line(100.0 * i, 0, 100.0 * i + 90, 0));
  const DetectionMatch match = MatchSlots(lines, lines);
  ASSERT_EQ(match.true_positives(), 8);
  const std::vector<SlotIdTruth> truth = {{"38", true},  {"39", true},  {"40", true},
                                          {"41", true},  {"42", false}, {"", true},
                                          {"43", false}, {"44", false}};
  const std::vector<std::string> read = {"38", "3?", "", "14", "42", "", "13", "4?"};
  IdCounts counts;
  AddIdCounts(match, read, truth, &counts);
  EXPECT_EQ(counts.readable, 4);  // "42", "43" and "44" are worn, "" has none
  EXPECT_EQ(counts.correct, 1);   // "3?" partial, "" unread, "14" wrong
  EXPECT_EQ(counts.unread, 1);
  EXPECT_EQ(counts.unreadable, 4);
  EXPECT_EQ(counts.invented, 2);        // "42" and "13" read where the truth is worn; "4?" partial
  EXPECT_EQ(counts.invented_right, 1);  // "42" is the worn paint's own ID
  EXPECT_DOUBLE_EQ(counts.accuracy(), 0.25);
}

TEST(IdCountsTest, UnmatchedSlotsDoNotCount) {
  const DetectionMatch match = MatchSlots({Line(0, 0, 150, 0), Line(500, 0, 650, 0)},
                                          {Line(0, 0, 150, 0), Line(0, 300, 150, 300)});
  IdCounts counts;
  EXPECT_DOUBLE_EQ(counts.accuracy(), 1.0);  // nothing to read yet
  AddIdCounts(match, {"7", "8"}, {{"7", true}, {"9", true}}, &counts);
  EXPECT_EQ(counts.readable, 1);
  EXPECT_EQ(counts.correct, 1);
  IdCounts total;
  total.Add(counts);
  total.Add(counts);
  EXPECT_EQ(total.correct, 2);
  EXPECT_THROW(AddIdCounts(match, {"7"}, {{"7", true}, {"9", true}}, &counts),
               std::invalid_argument);
}

}  // namespace
}  // namespace parkslam::eval
