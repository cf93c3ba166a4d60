// The paint check of slot candidates and the corner refinement on painted
// lines (slot_paint_check.h), and the pairing's rule against points inside
// a slot (slot_pairing.h), on drawn lots whose lines are known.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "parkslam/perception/slot_paint_check.h"
#include "parkslam/perception/slot_pairing.h"

namespace parkslam::perception {
namespace {

constexpr int kDrawnLineWidthPx = 9;  // 0.15 m at 60 px/m

// A grey floor with an entrance line along y = 200 (x 40 to 560) and
// separating lines 2.5 m apart at x = 100, 250, 400 and 550, 5 m deep,
// lightly blurred as a fused view is.
cv::Mat DrawnRow() {
  cv::Mat grey(600, 600, CV_8UC1, cv::Scalar(90));
  // Its own generator: the same floor whatever ran before (OpenCV's
  // global one would make each test depend on the order).
  cv::RNG rng(20);
  rng.fill(grey, cv::RNG::NORMAL, 90, 6);
  const cv::Scalar paint(230);
  cv::line(grey, {40, 200}, {560, 200}, paint, kDrawnLineWidthPx);
  for (const int x : {100, 250, 400, 550})
    cv::line(grey, {x, 200}, {x, 500}, paint, kDrawnLineWidthPx);
  cv::GaussianBlur(grey, grey, cv::Size(5, 5), 1.0);
  return grey;
}

DetectedSlot SlotBetween(double x0, double x1) {
  DetectedSlot slot;
  slot.corners_px = {Eigen::Vector2d(x0, 200), Eigen::Vector2d(x1, 200), Eigen::Vector2d(x1, 500),
                     Eigen::Vector2d(x0, 500)};
  slot.depth_dir_px = Eigen::Vector2d::UnitY();
  return slot;
}

TEST(SlotPaintCheckTest, FindsTheSeparatingLineOfAMissedPointAndNoneInATrueSlot) {
  const cv::Mat grey = DrawnRow();
  const SlotPaintCheckOptions options;
  // 100 -> 400 spans the line at x = 250, whose point was missed.
  const SlotPaint across = MeasureSlotPaint(grey, cv::Mat(), SlotBetween(100, 400), options);
  ASSERT_EQ(across.lines_inside.size(), 1u);
  // Within the 9 px stripe: the maximum of a flat top moves with the noise.
  EXPECT_NEAR(across.lines_inside[0].x(), 250.0, 3.0);
  EXPECT_NEAR(across.lines_inside[0].y(), 200.0, 1e-9);
  // Across two missed points.
  EXPECT_EQ(MeasureSlotPaint(grey, cv::Mat(), SlotBetween(100, 550), options).lines_inside.size(),
            2u);
  EXPECT_TRUE(
      MeasureSlotPaint(grey, cv::Mat(), SlotBetween(100, 250), options).lines_inside.empty());
}

TEST(SlotPaintCheckTest, DigitsAndCarBodiesInsideASlotAreNoSeparatingLine) {
  cv::Mat grey = DrawnRow();
  // Strokes of a painted ID in the slot's first metre, and a car's bright
  // body (1 m wide) over its whole depth.
  for (const int x : {150, 175, 200}) cv::line(grey, {x, 215}, {x, 250}, cv::Scalar(230), 6);
  cv::rectangle(grey, {290, 230}, {350, 480}, cv::Scalar(210), cv::FILLED);
  const SlotPaintCheckOptions options;
  EXPECT_TRUE(
      MeasureSlotPaint(grey, cv::Mat(), SlotBetween(100, 250), options).lines_inside.empty());
  EXPECT_TRUE(
      MeasureSlotPaint(grey, cv::Mat(), SlotBetween(250, 400), options).lines_inside.empty());
}

TEST(SlotPaintCheckTest, ASlotOutOfViewIsLeftAlone) {
  cv::Mat grey = DrawnRow();
  const SlotPaintCheckOptions options;
  // Masked (the car's footprint) over the slot's interior: nothing can be
  // said, though a line runs there.
  cv::Mat mask(grey.size(), CV_8UC1, cv::Scalar(255));
  mask(cv::Rect(90, 220, 330, 300)).setTo(0);
  EXPECT_TRUE(MeasureSlotPaint(grey, mask, SlotBetween(100, 400), options).lines_inside.empty());
  // Unmasked, the same slot shows its line (the check above can fail).
  EXPECT_EQ(MeasureSlotPaint(grey, cv::Mat(), SlotBetween(100, 400), options).lines_inside.size(),
            1u);
}

// A slot partly hidden (the car's footprint, or the image's border) still
// shows a line across the part in view, when that is most of it.
TEST(SlotPaintCheckTest, ACrossSectionMostlyInViewCounts) {
  const cv::Mat grey = DrawnRow();
  cv::Mat mask(grey.size(), CV_8UC1, cv::Scalar(255));
  mask(cv::Rect(340, 0, 100, 600)).setTo(0);  // 60 of the 300 px between the corners
  SlotPaintCheckOptions options;
  options.min_share_in_view = 1.0;
  EXPECT_TRUE(MeasureSlotPaint(grey, mask, SlotBetween(100, 400), options).lines_inside.empty());
  options.min_share_in_view = 0.7;
  const SlotPaint paint = MeasureSlotPaint(grey, mask, SlotBetween(100, 400), options);
  // (Two maxima of one wide stripe may both count: the detector merges
  // points closer than its NMS radius.)
  ASSERT_FALSE(paint.lines_inside.empty());
  for (const Eigen::Vector2d& at : paint.lines_inside) EXPECT_NEAR(at.x(), 250.0, 3.0);
  options.min_share_in_view = 0.0;
  std::string error;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("min_share_in_view"), std::string::npos) << error;
}

// The slot 250-400 of the drawn row, its neighbours' corners missed: the
// separating lines at 100 and 550 are where the row leads, one width on.
TEST(SlotPaintCheckTest, ARowLeadsToTheCornersNextToItsSlots) {
  const SlotPaintCheckOptions options;
  const std::vector<DetectedSlot> slots{SlotBetween(250, 400)};
  std::vector<Eigen::Vector2d> known{{250, 200}, {400, 200}};
  std::vector<RowCorner> corners =
      FindRowCorners(DrawnRow(), cv::Mat(), slots, known, 240.0, 18.0, options);
  ASSERT_EQ(corners.size(), 2u);
  EXPECT_LT((corners[0].px - Eigen::Vector2d(100, 200)).norm(), 3.0);
  EXPECT_LT((corners[1].px - Eigen::Vector2d(550, 200)).norm(), 3.0);
  EXPECT_EQ(corners[0].slot, 0);
  // A corner already known is not found again.
  known.emplace_back(101, 203);
  corners = FindRowCorners(DrawnRow(), cv::Mat(), slots, known, 240.0, 18.0, options);
  ASSERT_EQ(corners.size(), 1u);
  EXPECT_LT((corners[0].px - Eigen::Vector2d(550, 200)).norm(), 3.0);
  // Where the row ends (no line at 550) or the next line stands off the
  // width (at 520, 0.5 m short), nothing.
  cv::Mat ended = DrawnRow();
  cv::rectangle(ended, {540, 210}, {560, 510}, cv::Scalar(90), cv::FILLED);
  EXPECT_TRUE(FindRowCorners(ended, cv::Mat(), slots, known, 240.0, 18.0, options).empty());
  cv::line(ended, {520, 200}, {520, 500}, cv::Scalar(230), kDrawnLineWidthPx);
  EXPECT_TRUE(FindRowCorners(ended, cv::Mat(), slots, known, 240.0, 18.0, options).empty());
  // A parallel slot (wider than the limit) leads nowhere.
  EXPECT_TRUE(
      FindRowCorners(DrawnRow(), cv::Mat(), slots, {{250, 200}, {400, 200}}, 140.0, 18.0, options)
          .empty());
}

TEST(SlotPaintCheckTest, CornersMoveToTheCentrelinesCrossing) {
  const cv::Mat grey = DrawnRow();
  SlotPaintCheckOptions options;
  // The network's corners a few pixels off (its cells are 2.3 px wide),
  // its direction 3 degrees off, and the far corners 300 px behind.
  DetectedSlot slot = SlotBetween(250, 400);
  slot.corners_px[0] += Eigen::Vector2d(4.0, -3.0);
  slot.corners_px[1] += Eigen::Vector2d(-3.5, 4.5);
  const double off_rad = 3.0 * M_PI / 180.0;
  slot.depth_dir_px = Eigen::Vector2d(-std::sin(off_rad), std::cos(off_rad));
  slot.corners_px[2] = slot.corners_px[1] + 300.0 * slot.depth_dir_px;
  slot.corners_px[3] = slot.corners_px[0] + 300.0 * slot.depth_dir_px;
  EXPECT_EQ(RefineSlotCorners(grey, cv::Mat(), options, &slot), 2);
  // Drawn lines' centres: x = 250 and 400, y = 200 (a 9-px line drawn at
  // an integer centre).
  EXPECT_LT((slot.corners_px[0] - Eigen::Vector2d(250, 200)).norm(), 0.3);
  EXPECT_LT((slot.corners_px[1] - Eigen::Vector2d(400, 200)).norm(), 0.3);
  // The depth direction is the lines', and the far corners stand behind
  // the entrance along it, as deep as before.
  EXPECT_LT(std::abs(slot.depth_dir_px.x()), std::sin(0.3 * M_PI / 180.0));
  EXPECT_LT((slot.corners_px[2] - Eigen::Vector2d(400, 500)).norm(), 1.0);
  EXPECT_LT((slot.corners_px[3] - Eigen::Vector2d(250, 500)).norm(), 1.0);
  // A corner whose lines are not painted stays where it was.
  DetectedSlot bare = SlotBetween(250, 400);
  bare.corners_px[0] = bare.corners_px[3] = Eigen::Vector2d(250, 560);
  bare.corners_px[1] = Eigen::Vector2d(400, 560);
  bare.corners_px[2] = Eigen::Vector2d(400, 590);
  EXPECT_EQ(RefineSlotCorners(grey, cv::Mat(), options, &bare), 0);
  EXPECT_EQ(bare.corners_px[0], Eigen::Vector2d(250, 560));
}

TEST(SlotPaintCheckTest, AJunctionOfPaintIsSeenAtItsPointOnly) {
  const cv::Mat grey = DrawnRow();
  SlotPaintCheckOptions options;
  const double down = M_PI / 2.0;  // separating lines run to +y
  const double max_angle = 0.35;
  const double share = 0.7;
  // A T at (250, 200), an L at (550, 200) (entrance to one side only).
  for (const double x : {250.0, 550.0}) {
    const PointPaint at =
        MeasurePointPaint(grey, cv::Mat(), {x, 200.0}, down, max_angle, share, options);
    EXPECT_TRUE(at.in_view) << x;
    EXPECT_TRUE(at.separating) << x;
    EXPECT_TRUE(at.entrance) << x;
  }
  // A few pixels off still finds it: the network's point is that coarse.
  EXPECT_TRUE(MeasurePointPaint(grey, cv::Mat(), {254.0, 204.0}, down, max_angle, share, options)
                  .separating);
  // The L turned outwards, along where its entrance line would go on: no
  // paint there (a T turned a quarter is a junction still).
  const PointPaint turned =
      MeasurePointPaint(grey, cv::Mat(), {550.0, 200.0}, 0.0, max_angle, share, options);
  EXPECT_TRUE(turned.in_view);
  EXPECT_FALSE(turned.separating);
  // Bare floor between the lines: in view, no junction.
  const PointPaint floor =
      MeasurePointPaint(grey, cv::Mat(), {175.0, 350.0}, down, max_angle, share, options);
  EXPECT_TRUE(floor.in_view);
  EXPECT_FALSE(floor.separating);
  EXPECT_FALSE(floor.entrance);
  // The far end of a separating line: the line runs away from the point,
  // no entrance line crosses it.
  const PointPaint far_end =
      MeasurePointPaint(grey, cv::Mat(), {250.0, 500.0}, -down, max_angle, share, options);
  EXPECT_TRUE(far_end.separating);
  EXPECT_FALSE(far_end.entrance);
  // Off the image: nothing can be said.
  EXPECT_FALSE(
      MeasurePointPaint(grey, cv::Mat(), {-100.0, 200.0}, down, max_angle, share, options).in_view);
}

TEST(SlotPairingTest, AWeakPointInsideASlotIsDroppedWithItsSlots) {
  // A parallel slot 6 m long, and a weaker point 0.37 m inside it (painted
  // digits): it pairs with both ends into two false slots.
  std::vector<MarkingPoint> points(3);
  points[0].px = {100, 200};
  points[1].px = {460, 200};
  points[2].px = {280, 222};
  for (MarkingPoint& p : points) p.direction_rad = M_PI / 2;  // down, into the slots
  points[0].score = points[1].score = 0.9;
  points[2].score = 0.7;
  SlotPairingOptions options;
  options.require_entrance_facing_vehicle = false;
  options.drop_points_inside_slots = false;
  EXPECT_EQ(PairMarkingPoints(points, cv::Size(600, 600), options).size(), 3u);
  options.drop_points_inside_slots = true;
  const std::vector<DetectedSlot> slots = PairMarkingPoints(points, cv::Size(600, 600), options);
  ASSERT_EQ(slots.size(), 1u);
  EXPECT_EQ(std::min(slots[0].marking_points[0], slots[0].marking_points[1]), 0);
  EXPECT_EQ(std::max(slots[0].marking_points[0], slots[0].marking_points[1]), 1);
  // A point stronger than the slot's is kept, and so is every slot.
  points[2].score = 0.95;
  EXPECT_EQ(PairMarkingPoints(points, cv::Size(600, 600), options).size(), 3u);
}

}  // namespace
}  // namespace parkslam::perception
