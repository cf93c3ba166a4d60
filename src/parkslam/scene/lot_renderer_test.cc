#include "parkslam/scene/lot_renderer.h"

#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "parkslam/common/angles.h"
#include "parkslam/common/lot_constants.h"

namespace parkslam::scene {
namespace {

// A row of four slots ahead of the aisle (entrance line at y = 3 m, depth
// 5.3 m), a wall with a tag behind them, a pillar.
sim::World SmallLot() {
  sim::World world;
  world.name = "small";
  for (int k = 0; k < 4; ++k) {
    sim::WorldSlot slot;
    const double x0 = 0.0 + 2.5 * k;
    slot.corners_map = {Eigen::Vector2d(x0, 3.0), Eigen::Vector2d(x0 + 2.5, 3.0),
                        Eigen::Vector2d(x0 + 2.5, 8.3), Eigen::Vector2d(x0, 8.3)};
    slot.painted_id = std::to_string(11 + k);
    world.slots.push_back(slot);
  }
  sim::WorldWall wall;
  wall.a_map = Eigen::Vector2d(-5.0, 10.0);
  wall.b_map = Eigen::Vector2d(15.0, 10.0);
  wall.normal_map = Eigen::Vector2d(0.0, -1.0);
  world.walls.push_back(wall);
  sim::WorldPillar pillar;
  pillar.center_map = Eigen::Vector2d(-2.0, 9.0);
  world.pillars.push_back(pillar);
  sim::WorldTag tag;
  tag.tag_id = 3;
  tag.p_map = Eigen::Vector2d(5.0, 10.0);
  tag.normal_yaw_rad = -kPi / 2;
  tag.size_m = kDefaultTagSize_m;
  tag.mount_index = 0;
  world.tags.push_back(tag);
  return world;
}

const LotRenderer& Lot() {
  static const LotRenderer renderer = [] {
    LotLook look;
    look.preset = "epoxy";
    look.seed = 4;
    look.parked_share = 0.0;
    return LotRenderer(SmallLot(), camera::DefaultRig(), look);
  }();
  return renderer;
}

float GreyAt(const cv::Mat& bgr, const Eigen::Vector2d& px) {
  const cv::Vec3b v = bgr.at<cv::Vec3b>(static_cast<int>(std::lround(px.y())),
                                        static_cast<int>(std::lround(px.x())));
  return (v[0] + v[1] + v[2]) / 3.0f;
}

// Pearson correlation of two equally long samples.
double Correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = static_cast<double>(a.size());
  double ma = 0, mb = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    ma += a[i] / n;
    mb += b[i] / n;
  }
  double ab = 0, aa = 0, bb = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    ab += (a[i] - ma) * (b[i] - mb);
    aa += (a[i] - ma) * (a[i] - ma);
    bb += (b[i] - mb) * (b[i] - mb);
  }
  return ab / std::sqrt(aa * bb + 1e-12);
}

TEST(LotRendererTest, TheFloorStaysInPlaceAsTheCarMoves) {
  // Driving along the row: the slots' floor, seen by the left camera from
  // two poses 0.6 m and 0.05 rad apart, shows the same paint at the same
  // map points; 0.3 m off it does not.
  const SE2 a(2.0, 1.2, 0.0), b(2.6, 1.3, 0.05);
  const RenderedScene ra = Lot().Render(a, 1000, {});
  const RenderedScene rb = Lot().Render(b, 2000, {});
  const camera::TopViewFusion& fusion = Lot().renderer().FusionOf(Lot().lot());
  std::vector<double> in_a, in_b, in_b_off;
  for (double x = 2.0; x <= 6.0; x += 0.04) {
    for (double y = 2.6; y <= 4.5; y += 0.04) {
      const Eigen::Vector2d p(x, y);
      in_a.push_back(GreyAt(ra.top_view, fusion.VehicleToPixel(a.inverse() * p)));
      in_b.push_back(GreyAt(rb.top_view, fusion.VehicleToPixel(b.inverse() * p)));
      in_b_off.push_back(GreyAt(
          rb.top_view, fusion.VehicleToPixel(b.inverse() * (p + Eigen::Vector2d(0.3, 0.0)))));
    }
  }
  const double same = Correlation(in_a, in_b), off = Correlation(in_a, in_b_off);
  EXPECT_GT(same, 0.7) << "off by 0.3 m: " << off;
  EXPECT_GT(same, off + 0.3) << "same " << same;
}

TEST(LotRendererTest, SlotLinesShowBrighterThanTheFloor) {
  const SE2 pose(5.0, 0.0, kPi / 2);
  const RenderedScene r = Lot().Render(pose, 1000, {});
  const camera::TopViewFusion& fusion = Lot().renderer().FusionOf(Lot().lot());
  // Along the separating line at x = 5 and beside it in the slot.
  double line = 0.0, floor = 0.0;
  for (double y = 3.5; y <= 5.5; y += 0.1) {
    line += GreyAt(r.top_view, fusion.VehicleToPixel(pose.inverse() * Eigen::Vector2d(5.0, y)));
    floor += GreyAt(r.top_view, fusion.VehicleToPixel(pose.inverse() * Eigen::Vector2d(5.6, y)));
  }
  EXPECT_GT((line - floor) / 21.0, 20.0) << line / 21.0 << " vs " << floor / 21.0;
}

TEST(LotRendererTest, TheFrontCameraSeesTheTagLibapriltagDecodes) {
  RenderRequest request;
  request.front = true;
  request.top_view = false;
  const RenderedScene r = Lot().Render(SE2(5.0, 1.0, kPi / 2), 1000, request);
  ASSERT_FALSE(r.front.empty());
  cv::Mat grey;
  cv::cvtColor(r.front, grey, cv::COLOR_BGR2GRAY);
  apriltag_family_t* family = tag36h11_create();
  apriltag_detector_t* detector = apriltag_detector_create();
  apriltag_detector_add_family(detector, family);
  detector->nthreads = 1;
  image_u8_t image{grey.cols, grey.rows, static_cast<int32_t>(grey.step), grey.data};
  zarray_t* detections = apriltag_detector_detect(detector, &image);
  std::vector<int> ids;
  for (int i = 0; i < zarray_size(detections); ++i) {
    apriltag_detection_t* d = nullptr;
    zarray_get(detections, i, &d);
    ids.push_back(d->id);
  }
  apriltag_detections_destroy(detections);
  apriltag_detector_destroy(detector);
  tag36h11_destroy(family);
  EXPECT_EQ(ids, std::vector<int>{3});
}

TEST(LotRendererTest, SamePoseAndTimeSameBytesOtherTimeOtherNoise) {
  const SE2 pose(4.0, 0.5, 1.4);
  const RenderedScene a = Lot().Render(pose, 5000, {});
  const RenderedScene b = Lot().Render(pose, 5000, {});
  const RenderedScene c = Lot().Render(pose, 6000, {});
  EXPECT_EQ(cv::norm(a.top_view, b.top_view, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a.top_view, c.top_view, cv::NORM_L1), 0.0);
}

TEST(LotRendererTest, RejectsAnUnknownLook) {
  LotLook look;
  look.preset = "marble";
  EXPECT_THROW(LotRenderer(SmallLot(), camera::DefaultRig(), look), std::invalid_argument);
}

}  // namespace
}  // namespace parkslam::scene
