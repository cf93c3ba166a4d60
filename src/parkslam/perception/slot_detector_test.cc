#include "parkslam/perception/slot_detector.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "parkslam/common/angles.h"

namespace parkslam::perception {
namespace {

constexpr double kPxPerM = 60.0;
constexpr double kLineWidthPx = 9.0;  // 0.15 m, as the renderer paints

// A synthetic top view: concrete with grain, and painted stripes drawn as
// the renderer draws them (each stripe extended by half its width beyond
// both ends, so that stripes meeting at a corner join squarely).
class TopView {
 public:
  TopView() : image_(600, 600, CV_8UC1, cv::Scalar(96)) {
    cv::Mat grain(image_.size(), CV_8S);
    cv::RNG rng(7);
    rng.fill(grain, cv::RNG::NORMAL, 0.0, 4.0);
    cv::add(image_, grain, image_, cv::noArray(), CV_8U);
  }

  void Stripe(const Eigen::Vector2d& p, const Eigen::Vector2d& q, double grey = 225.0) {
    const Eigen::Vector2d d = (q - p).normalized();
    const Eigen::Vector2d n(-d.y(), d.x());
    const double h = kLineWidthPx / 2;
    const Eigen::Vector2d a = p - d * h, b = q + d * h;
    const std::array<Eigen::Vector2d, 4> quad = {a - n * h, b - n * h, b + n * h, a + n * h};
    std::array<cv::Point, 4> pts;
    for (int i = 0; i < 4; ++i) {
      pts[static_cast<size_t>(i)] = cv::Point(static_cast<int>(std::lround(quad[i].x() * 16)),
                                              static_cast<int>(std::lround(quad[i].y() * 16)));
    }
    cv::fillConvexPoly(image_, pts.data(), 4, cv::Scalar(grey), cv::LINE_AA, 4);
  }

  // A slot (paper Fig. 3): separating lines from both entrance corners
  // along `depth` (unit, image frame) and entrance stubs of 0.5 m.
  void Slot(const Eigen::Vector2d& c0, const Eigen::Vector2d& c1, const Eigen::Vector2d& depth,
            double depth_m = 5.3, double grey = 225.0) {
    const Eigen::Vector2d e = (c1 - c0).normalized();
    Stripe(c0, c0 + depth * depth_m * kPxPerM, grey);
    Stripe(c1, c1 + depth * depth_m * kPxPerM, grey);
    Stripe(c0, c0 + e * 0.5 * kPxPerM, grey);
    Stripe(c1, c1 - e * 0.5 * kPxPerM, grey);
  }

  const cv::Mat& image() const { return image_; }
  cv::Mat& image() { return image_; }

 private:
  cv::Mat image_;
};

const DetectedSlot* FindSlot(const SlotDetection& d, const Eigen::Vector2d& c0,
                             const Eigen::Vector2d& c1, double tolerance_px = 2.0) {
  for (const DetectedSlot& s : d.slots) {
    if ((s.corners_px[0] - c0).norm() < tolerance_px &&
        (s.corners_px[1] - c1).norm() < tolerance_px) {
      return &s;
    }
  }
  return nullptr;
}

const MarkingPoint* FindPoint(const SlotDetection& d, const Eigen::Vector2d& p,
                              double tolerance_px = 2.0) {
  for (const MarkingPoint& m : d.marking_points) {
    if ((m.px - p).norm() < tolerance_px) return &m;
  }
  return nullptr;
}

// A row of three perpendicular slots above the car, opening downwards.
TEST(SlotDetectorTest, FindsARowOfPerpendicularSlotsToAPixel) {
  TopView view;
  const double w = 2.5 * kPxPerM;
  const Eigen::Vector2d up(0.0, -1.0);
  const std::array<Eigen::Vector2d, 4> corners = {
      Eigen::Vector2d(75.3, 200.6), Eigen::Vector2d(75.3 + w, 200.6),
      Eigen::Vector2d(75.3 + 2 * w, 200.6), Eigen::Vector2d(75.3 + 3 * w, 200.6)};
  for (int k = 0; k < 3; ++k) view.Slot(corners[k], corners[k + 1], up);
  const SlotDetection d = SlotDetector().Detect(view.image());

  ASSERT_EQ(d.marking_points.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    const MarkingPoint* p = FindPoint(d, corners[k], 1.0);
    ASSERT_NE(p, nullptr) << "corner " << k;
    EXPECT_EQ(p->shape, k == 0 || k == 3 ? MarkingShape::kL : MarkingShape::kT) << "corner " << k;
    EXPECT_NEAR(AngleDiff(p->direction_rad, -kPi / 2), 0.0, DegToRad(2.0)) << "corner " << k;
  }
  ASSERT_EQ(d.slots.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    const DetectedSlot* s = FindSlot(d, corners[k], corners[k + 1], 1.0);
    ASSERT_NE(s, nullptr) << "slot " << k;
    // Far corners guessed at the standard depth, and marked so.
    EXPECT_NEAR((s->corners_px[3] - s->corners_px[0]).norm(), 5.3 * kPxPerM, 2.0);
    EXPECT_LT(s->corners_px[3].y(), s->corners_px[0].y());
    EXPECT_TRUE(s->corner_observed[0] && s->corner_observed[1]);
    EXPECT_FALSE(s->corner_observed[2] || s->corner_observed[3]);
    EXPECT_GT(s->confidence, 0.5);
  }
}

// Paper III-A: an entrance-line candidate containing more than two marking
// points is removed. Three T/L points 2.5 m apart: the outer pair (5 m, a
// plausible parallel slot by length) has the middle point on it.
TEST(SlotDetectorTest, RemovesEntranceCandidatesWithAThirdMarkingPoint) {
  TopView with_middle, without_middle;
  const Eigen::Vector2d a(150, 180), b(300, 180), c(450, 180), up(0, -1);
  with_middle.Slot(a, b, up);
  with_middle.Slot(b, c, up);
  // The same outer points without the middle junction: one 5 m entrance.
  without_middle.Slot(a, c, up, 2.5);
  const SlotDetector detector;
  const SlotDetection d1 = detector.Detect(with_middle.image());
  EXPECT_EQ(d1.slots.size(), 2u);
  EXPECT_EQ(FindSlot(d1, a, c), nullptr);
  const SlotDetection d2 = detector.Detect(without_middle.image());
  ASSERT_EQ(d2.slots.size(), 1u);
  ASSERT_NE(FindSlot(d2, a, c), nullptr);
  // A 5 m entrance is a parallel slot: its far corners at the parallel depth.
  EXPECT_NEAR((d2.slots[0].corners_px[3] - a).norm(), 2.5 * kPxPerM, 2.0);
}

// Where the middle corner of two perpendicular slots is missed (its
// separating line stops short of the entrance line), the outer pair is no
// parallel slot: that separating line still ends on it between them.
TEST(SlotDetectorTest, RemovesEntranceCandidatesWithASeparatingLineBetween) {
  TopView view;
  const Eigen::Vector2d a(150, 180), b(300, 180), c(450, 180), up(0, -1);
  view.Slot(a, c, up, 5.3);
  view.Stripe(a, c);
  // Its paint ends 0.225 m from the entrance line's centre (the stripe
  // reaches half its width beyond its end point): within on_line_tolerance_m.
  view.Stripe(b + up * 0.3 * kPxPerM, b + up * 5.3 * kPxPerM);
  const SlotDetection d = SlotDetector().Detect(view.image());
  ASSERT_NE(FindPoint(d, a, 2.0), nullptr);
  ASSERT_NE(FindPoint(d, c, 2.0), nullptr);
  ASSERT_EQ(FindPoint(d, b, 20.0), nullptr);  // the middle corner is missed
  EXPECT_EQ(FindSlot(d, a, c), nullptr);
  EXPECT_TRUE(d.slots.empty());
}

// A separating line is a stem, also where an L's shorter arm is taken as
// it: a 5.3 m line with 0.5 m strokes at both ends (a row's end line) is no
// parallel slot; with 2.5 m side lines it is one.
TEST(SlotDetectorTest, ParallelSlotNeedsSideLinesNotStubs) {
  const Eigen::Vector2d a(100, 140), c(100, 140 + 5.3 * kPxPerM), left(-1, 0);
  const SlotDetector detector;
  for (const double side_m : {0.5, 2.5}) {
    TopView view;
    view.Stripe(a, c);
    view.Stripe(a, a + left * side_m * kPxPerM);
    view.Stripe(c, c + left * side_m * kPxPerM);
    const SlotDetection d = detector.Detect(view.image());
    ASSERT_NE(FindPoint(d, a, 2.0), nullptr) << side_m;
    ASSERT_NE(FindPoint(d, c, 2.0), nullptr) << side_m;
    EXPECT_EQ(d.slots.size(), side_m < 1.0 ? 0u : 1u) << side_m;
  }
}

// Extremely small or large candidates are discarded: entrances on both
// sides of min_entrance_m (2.0 m) and max_entrance_m (7.5 m).
TEST(SlotDetectorTest, DiscardsEntrancesOutsideTheLengthLimits) {
  const SlotDetector detector;
  const Eigen::Vector2d up(0, -1);
  for (const auto& [length_m, expected] :
       std::vector<std::pair<double, size_t>>{{1.85, 0}, {2.15, 1}, {7.3, 1}, {7.7, 0}}) {
    TopView view;
    const Eigen::Vector2d a(300 - length_m * kPxPerM / 2, 150);
    const Eigen::Vector2d b(300 + length_m * kPxPerM / 2, 150);
    view.Slot(a, b, up, 2.0);
    const SlotDetection d = detector.Detect(view.image());
    EXPECT_EQ(d.slots.size(), expected) << length_m << " m";
    EXPECT_EQ(d.marking_points.size(), 2u) << length_m << " m";
  }
}

// Angled slots (60 degrees between the separating lines and the entrance).
TEST(SlotDetectorTest, FindsAngledSlots) {
  TopView view;
  const double angle = DegToRad(60.0);
  const Eigen::Vector2d depth(std::cos(angle), -std::sin(angle));
  const double entrance_px = 2.5 / std::sin(angle) * kPxPerM;
  const Eigen::Vector2d c0(120, 220), c1 = c0 + Eigen::Vector2d(entrance_px, 0),
                                      c2 = c1 + Eigen::Vector2d(entrance_px, 0);
  view.Slot(c0, c1, depth);
  view.Slot(c1, c2, depth);
  const SlotDetection d = SlotDetector().Detect(view.image());
  ASSERT_EQ(d.slots.size(), 2u);
  for (const DetectedSlot& s : d.slots) {
    EXPECT_NEAR(std::acos(s.depth_dir_px.dot(depth)), 0.0, DegToRad(2.0));
  }
  const MarkingPoint* middle = FindPoint(d, c1, 1.5);
  ASSERT_NE(middle, nullptr);
  EXPECT_EQ(middle->shape, MarkingShape::kT);
  EXPECT_NEAR(AngleDiff(middle->direction_rad, std::atan2(depth.y(), depth.x())), 0.0,
              DegToRad(2.0));
}

// Slots open towards the car: a pair whose slot would lie on the car's side
// of the entrance (a painted back line, seen from the aisle) is no slot.
TEST(SlotDetectorTest, IgnoresSlotsOpeningAwayFromTheCar) {
  TopView view;
  // Separating lines run down, towards the image centre.
  view.Slot({150, 100}, {300, 100}, {0, 1}, 2.0);
  SlotDetectorOptions options;
  EXPECT_TRUE(SlotDetector(options).Detect(view.image()).slots.empty());
  options.require_entrance_facing_vehicle = false;
  EXPECT_EQ(SlotDetector(options).Detect(view.image()).slots.size(), 1u);
}

// Strokes shorter than a separating line (painted digits) make no
// marking points; nor does paint under the mask.
TEST(SlotDetectorTest, ShortStrokesAndMaskedPaintMakeNoMarkingPoints) {
  TopView view;
  // A "4"-like pattern of 0.35 m strokes.
  view.Stripe({300, 100}, {300, 121});
  view.Stripe({300, 121}, {320, 121});
  view.Stripe({320, 100}, {320, 142});
  // A full slot under the mask.
  view.Slot({150, 450}, {300, 450}, {0, 1}, 1.5);
  cv::Mat mask(view.image().size(), CV_8UC1, cv::Scalar(255));
  mask(cv::Rect(100, 380, 260, 200)).setTo(0);
  SlotDetectorOptions options;
  options.require_entrance_facing_vehicle = false;
  const SlotDetection d = SlotDetector(options).Detect(view.image(), mask);
  EXPECT_TRUE(d.marking_points.empty());
  EXPECT_TRUE(d.slots.empty());
}

// Worn paint next to glare: a slot painted 44 grey levels above the floor,
// dark specks (oil, tile joints) along its lines, and a bright glare stripe
// (which sets the brightest paint in view, 0.35 of which is above the
// slot's contrast). The slot is still found, against its own contrast.
TEST(SlotDetectorTest, FindsAFaintSlotAmongSpecksAndGlare) {
  TopView view;
  const Eigen::Vector2d c0(150.4, 200.2), c1(300.4, 200.2), up(0.0, -1.0);
  view.Slot(c0, c1, up, 2.5, 140.0);
  view.Stripe({480, 40}, {480, 560}, 255.0);
  cv::RNG rng(3);
  for (int k = 0; k < 40; ++k) {
    const double x = k % 2 == 0 ? c0.x() : c1.x();
    const double y = 200.0 - rng.uniform(0.0, 150.0);
    cv::circle(view.image(),
               cv::Point(static_cast<int>(x + (k % 4 < 2 ? -9 : 9)), static_cast<int>(y)), 2,
               cv::Scalar(20), cv::FILLED);
  }
  const SlotDetection d = SlotDetector().Detect(view.image());
  EXPECT_NE(FindPoint(d, c0, 1.5), nullptr);
  EXPECT_NE(FindPoint(d, c1, 1.5), nullptr);
  EXPECT_NE(FindSlot(d, c0, c1, 1.5), nullptr);
}

// Junctions among many lines (a car's body, grass) are rejected: an L
// corner keeps its marking point with four strokes passing 0.9 m from it,
// and loses it with five (max_lines_nearby = 4 within 1 m).
TEST(SlotDetectorTest, RejectsJunctionsAmongManyLines) {
  const Eigen::Vector2d corner(300.3, 300.2);
  const auto detect_with = [&](int distractors) {
    TopView view;
    view.Stripe(corner, corner + Eigen::Vector2d(0, -1.5 * kPxPerM));
    view.Stripe(corner, corner + Eigen::Vector2d(0.5 * kPxPerM, 0));
    // Radial strokes from 0.9 to 2 m, away from the corner's two arms
    // (up and right).
    const std::array<double, 6> angles_deg = {45, 90, 135, 180, 225, 315};
    for (int k = 0; k < distractors; ++k) {
      const double a = DegToRad(angles_deg[static_cast<size_t>(k)]);
      const Eigen::Vector2d u(std::cos(a), std::sin(a));
      view.Stripe(corner + 0.9 * kPxPerM * u, corner + 2.0 * kPxPerM * u);
    }
    SlotDetectorOptions options;
    options.require_entrance_facing_vehicle = false;
    return SlotDetector(options).Detect(view.image());
  };
  ASSERT_EQ(SlotDetectorOptions().max_lines_nearby, 4);
  const SlotDetection few = detect_with(4);
  ASSERT_NE(FindPoint(few, corner, 1.5), nullptr);
  EXPECT_EQ(FindPoint(few, corner, 1.5)->shape, MarkingShape::kL);
  EXPECT_EQ(FindPoint(detect_with(5), corner, 1.5), nullptr);
}

// The bright rim of a shadow's edge stands above the floor's median like
// paint, but on one side only: a painted line running into it makes no
// marking point, while the same line meeting a painted line does.
TEST(SlotDetectorTest, AShadowsEdgeIsNoPaintedLine) {
  const auto detect = [](bool painted) {
    TopView view;
    if (painted) {
      view.Stripe({300, 100}, {300, 500});
    } else {
      // Lit floor right of x = 300 with the bright rim that sharpening
      // leaves along a shadow's edge.
      view.image()(cv::Rect(300, 0, 300, 600)) += cv::Scalar(54);
      view.image()(cv::Rect(300, 0, 8, 600)) += cv::Scalar(40);
    }
    view.Stripe({296, 300}, {150, 300});
    SlotDetectorOptions options;
    options.require_entrance_facing_vehicle = false;
    return SlotDetector(options).Detect(view.image());
  };
  const SlotDetection lit = detect(false);
  EXPECT_TRUE(lit.marking_points.empty());
  const SlotDetection painted = detect(true);
  ASSERT_EQ(painted.marking_points.size(), 1u);
  EXPECT_EQ(painted.marking_points[0].shape, MarkingShape::kT);
}

// What a fused view paints pure black (no camera sees it) is masked like
// the mask: the same marking points either way, and the slot in view kept.
TEST(SlotDetectorTest, PureBlackRegionsAreMasked) {
  TopView view;
  const Eigen::Vector2d c0(100.4, 300.2), c1(250.4, 300.2), up(0.0, -1.0);
  view.Slot(c0, c1, up, 2.5);
  view.Slot({360.4, 300.2}, {510.4, 300.2}, up, 2.5);
  const cv::Rect unseen(330, 240, 220, 120);
  view.image()(unseen).setTo(0);
  cv::Mat mask(view.image().size(), CV_8UC1, cv::Scalar(255));
  mask(unseen).setTo(0);
  SlotDetectorOptions options;
  options.require_entrance_facing_vehicle = false;
  const SlotDetector detector(options);
  const SlotDetection black = detector.Detect(view.image());
  const SlotDetection masked = detector.Detect(view.image(), mask);
  ASSERT_EQ(black.marking_points.size(), masked.marking_points.size());
  for (size_t k = 0; k < black.marking_points.size(); ++k) {
    EXPECT_LT((black.marking_points[k].px - masked.marking_points[k].px).norm(), 1e-9);
  }
  EXPECT_EQ(black.marking_points.size(), 2u);
  EXPECT_NE(FindSlot(black, c0, c1, 1.5), nullptr);
}

TEST(SlotDetectorTest, RejectsInvalidOptionsAndImages) {
  SlotDetectorOptions options;
  options.min_entrance_m = 8.0;  // above max_entrance_m
  EXPECT_THROW(SlotDetector{options}, std::invalid_argument);
  options = {};
  options.min_stem_m = 0.1;  // below min_arm_m
  EXPECT_THROW(SlotDetector{options}, std::invalid_argument);
  options = {};
  options.max_lines_nearby = -1;
  EXPECT_THROW(SlotDetector{options}, std::invalid_argument);
  options = {};
  options.line_relative_contrast = 0.0;
  EXPECT_THROW(SlotDetector{options}, std::invalid_argument);
  const SlotDetector detector;
  EXPECT_THROW(detector.Detect(cv::Mat()), std::invalid_argument);
  EXPECT_THROW(detector.Detect(cv::Mat(100, 100, CV_32F, cv::Scalar(0))), std::invalid_argument);
  EXPECT_THROW(detector.Detect(cv::Mat(100, 100, CV_8UC1), cv::Mat(50, 50, CV_8UC1)),
               std::invalid_argument);
  // An empty floor: nothing, and no failure.
  const SlotDetection d = detector.Detect(cv::Mat(600, 600, CV_8UC1, cv::Scalar(96)));
  EXPECT_TRUE(d.marking_points.empty());
}

}  // namespace
}  // namespace parkslam::perception
