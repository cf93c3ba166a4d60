#include "parkslam/camera/top_view.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <tuple>

namespace parkslam::camera {
namespace {

const std::vector<std::string> kFisheyes{"front", "rear", "left", "right"};

// Renders what a camera of the rig sees of a ground with white dots of
// radius 6 cm on a 1 m grid (offset by 0.5 m), black elsewhere.
cv::Mat RenderDots(const CameraConfig& camera) {
  const CameraModel model(camera.intrinsics);
  cv::Mat image(camera.intrinsics.height, camera.intrinsics.width, CV_8UC1, cv::Scalar(0));
  for (int v = 0; v < image.rows; ++v) {
    for (int u = 0; u < image.cols; ++u) {
      const auto ray = model.Unproject({u, v});
      if (!ray) continue;
      const Eigen::Vector3d d = camera.T_vehicle_camera.linear() * *ray;
      const Eigen::Vector3d o = camera.T_vehicle_camera.translation();
      if (d.z() >= -1e-6) continue;
      const Eigen::Vector3d g = o - o.z() / d.z() * d;
      const double fx = g.x() - 0.5 - std::round(g.x() - 0.5);
      const double fy = g.y() - 0.5 - std::round(g.y() - 0.5);
      if (std::hypot(fx, fy) < 0.06) image.at<uint8_t>(v, u) = 255;
    }
  }
  return image;
}

std::vector<cv::Mat> RenderAll(const CameraRig& rig) {
  std::vector<cv::Mat> images;
  for (const std::string& name : kFisheyes) images.push_back(RenderDots(*rig.Find(name)));
  return images;
}

TEST(TopViewTest, PixelAndVehicleConversionsAreInverse) {
  const TopViewFusion fusion(DefaultRig(), kFisheyes);
  const Eigen::Vector2d p(3.2, -1.7);
  EXPECT_TRUE(fusion.PixelToVehicle(fusion.VehicleToPixel(p)).isApprox(p, 1e-12));
  // The car points up: a point ahead is above the centre, one on the left
  // is left of it.
  const Eigen::Vector2d c = fusion.VehicleToPixel({1.4, 0.0});
  EXPECT_NEAR(c.x(), 299.5, 1e-9);
  EXPECT_LT(fusion.VehicleToPixel({3.0, 0.0}).y(), c.y());
  EXPECT_LT(fusion.VehicleToPixel({1.4, 1.0}).x(), c.x());
}

class TopViewLookupTest : public ::testing::TestWithParam<std::tuple<FusionLookup, SeamStyle>> {};

TEST_P(TopViewLookupTest, GroundPointsLandAtTheirPredictedPixels) {
  const CameraRig rig = DefaultRig();
  const auto [lookup, seams] = GetParam();
  TopViewOptions options;
  options.seam_style = seams;
  const TopViewFusion fusion(rig, kFisheyes, options);
  const cv::Mat top = fusion.Fuse(RenderAll(rig), lookup);
  ASSERT_EQ(top.rows, 600);
  cv::Mat binary;
  cv::threshold(top, binary, 100, 255, cv::THRESH_BINARY);
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(binary, labels, stats, centroids);
  int checked = 0;
  double worst = 0.0;
  Eigen::Vector2d bias = Eigen::Vector2d::Zero();
  for (double x = -3.5; x <= 6.5; x += 1.0) {
    for (double y = -4.5; y <= 4.5; y += 1.0) {
      const Eigen::Vector2d expected = fusion.VehicleToPixel({x, y});
      if (expected.x() < 10 || expected.y() < 10 || expected.x() > 589 || expected.y() > 589)
        continue;
      // The blob nearest the expected pixel.
      Eigen::Vector2d best(1e9, 1e9);
      for (int i = 1; i < n; ++i) {
        const Eigen::Vector2d offset(centroids.at<double>(i, 0) - expected.x(),
                                     centroids.at<double>(i, 1) - expected.y());
        if (offset.norm() < best.norm()) best = offset;
      }
      if (best.norm() > 5.0) continue;  // under the car's footprint
      worst = std::max(worst, best.norm());
      bias += best;
      ++checked;
    }
  }
  EXPECT_GT(checked, 60);
  // Each value from the nearest camera pixel moves a dot's edges by up to
  // half a camera pixel, more than a top-view pixel far from the cameras;
  // on average nothing moves (no half-pixel shift).
  EXPECT_LT(worst, lookup == FusionLookup::kBilinear ? 1.0 : 1.5);
  EXPECT_LT((bias / checked).norm(), 0.15) << (bias / checked).transpose();
}

INSTANTIATE_TEST_SUITE_P(
    BothLookupsBothSeams, TopViewLookupTest,
    ::testing::Combine(::testing::Values(FusionLookup::kBilinear, FusionLookup::kNearest),
                       ::testing::Values(SeamStyle::kOpticalAxis, SeamStyle::kFootprintRays)));

// The nearest lookup takes each value from one camera pixel: where one
// camera alone is seen, a black-and-white ground stays black and white;
// the bilinear lookup mixes neighbours into greys at the dots' edges.
TEST(TopViewTest, NearestLookupMakesNoNewValues) {
  const CameraRig rig = DefaultRig();
  const TopViewFusion fusion(rig, kFisheyes);
  const std::vector<cv::Mat> images = RenderAll(rig);
  const cv::Mat nearest = fusion.Fuse(images, FusionLookup::kNearest);
  const cv::Mat bilinear = fusion.Fuse(images);
  int alone = 0, grey_nearest = 0, grey_bilinear = 0;
  for (int v = 0; v < nearest.rows; ++v) {
    for (int u = 0; u < nearest.cols; ++u) {
      if (fusion.PrimaryCamera(u, v) < 0 || fusion.PrimaryWeight(u, v) < 1.0) continue;
      ++alone;
      const int a = nearest.at<uint8_t>(v, u), b = bilinear.at<uint8_t>(v, u);
      if (a != 0 && a != 255) ++grey_nearest;
      if (b != 0 && b != 255) ++grey_bilinear;
    }
  }
  EXPECT_GT(alone, 100000);
  EXPECT_EQ(grey_nearest, 0);
  EXPECT_GT(grey_bilinear, 1000);
}

// A camera's priority widens the part of the view it is primary for; the
// default (none) is the plain closest-to-the-axis rule.
TEST(TopViewTest, CameraPriorityMovesTheSeams) {
  const auto count_left = [](const TopViewFusion& fusion) {
    int n = 0;
    for (int v = 0; v < 600; v += 3) {
      for (int u = 0; u < 600; u += 3) n += fusion.PrimaryCamera(u, v) == 2;  // "left"
    }
    return n;
  };
  TopViewOptions plain;
  plain.blend_angle_rad = 0.0;
  TopViewOptions wide = plain;
  wide.camera_priority_rad = {0.0, 0.0, 0.5, 0.5};
  const int before = count_left(TopViewFusion(DefaultRig(), kFisheyes, plain));
  const int after = count_left(TopViewFusion(DefaultRig(), kFisheyes, wide));
  EXPECT_GT(after, before * 5 / 4);
  // Primary alone (no blend): every seen pixel has no second camera.
  EXPECT_EQ(TopViewFusion(DefaultRig(), kFisheyes, plain).SecondaryCamera(20, 20), -1);
  TopViewOptions wrong = plain;
  wrong.camera_priority_rad = {0.1, 0.2};
  EXPECT_THROW(TopViewFusion(DefaultRig(), kFisheyes, wrong), std::invalid_argument);
  wrong.camera_priority_rad = {0.0, 0.0, 2.0, 0.0};
  EXPECT_THROW(TopViewFusion(DefaultRig(), kFisheyes, wrong), std::invalid_argument);
}

// Straight seams from the footprint's corners: the front camera owns a
// wedge ahead of the car bounded by straight lines at the asked angle; with
// the optical-axis rule (and this rig) its part reaches nearly the whole
// far edge of the view.
TEST(TopViewTest, FootprintRaysDrawStraightSeamsAtTheirAngle) {
  TopViewOptions axis;
  axis.blend_angle_rad = 0.0;
  TopViewOptions rays = axis;
  rays.seam_style = SeamStyle::kFootprintRays;
  rays.seam_front_angle_rad = 0.5;
  rays.seam_rear_angle_rad = 0.3;
  const TopViewFusion by_axis(DefaultRig(), kFisheyes, axis);
  const TopViewFusion by_rays(DefaultRig(), kFisheyes, rays);
  // The front camera's left edge, row by row, from the footprint's front
  // edge (row 102) to the top of the view; its largest distance from the
  // straight line through its two ends.
  const auto seam_bend_px = [](const TopViewFusion& fusion) {
    std::vector<int> left;
    for (int v = 0; v <= 95; ++v) {
      int u = 0;
      while (u < 600 && fusion.PrimaryCamera(u, v) != 0) ++u;
      left.push_back(u);
    }
    double worst = 0.0;
    for (size_t v = 0; v < left.size(); ++v) {
      const double line = left.back() + (left.front() - left.back()) *
                                            static_cast<double>(left.size() - 1 - v) /
                                            static_cast<double>(left.size() - 1);
      worst = std::max(worst, std::abs(left[v] - line));
    }
    return worst;
  };
  EXPECT_LT(seam_bend_px(by_rays), 1.5);
  const auto front_in_row = [](const TopViewFusion& fusion, int v) {
    int n = 0;
    for (int u = 0; u < 600; ++u) n += fusion.PrimaryCamera(u, v) == 0;
    return n;
  };
  EXPECT_GT(front_in_row(by_axis, 0), 500);
  // Row 0 lies 6.39 m ahead of the axle, 2.69 m past the footprint:
  // 1.85 m + 2 tan(0.5) 2.69 m = 4.79 m, 288 px.
  EXPECT_NEAR(front_in_row(by_rays, 0), 288, 3);

  // On either side of each seam, seen from its corner (x_front 3.7 m,
  // x_rear -1 m, half width 0.925 m); 2 m out along the direction.
  const auto at = [&](double corner_x, double sign_x, double sign_y, double angle) {
    const Eigen::Vector2d p(corner_x + sign_x * 2.0 * std::cos(angle),
                            sign_y * (0.925 + 2.0 * std::sin(angle)));
    const Eigen::Vector2d px = by_rays.VehicleToPixel(p);
    return by_rays.PrimaryCamera(static_cast<int>(px.x()), static_cast<int>(px.y()));
  };
  EXPECT_EQ(at(3.7, 1, 1, 0.4), 0);    // front, left of the axis
  EXPECT_EQ(at(3.7, 1, 1, 0.6), 2);    // left
  EXPECT_EQ(at(3.7, 1, -1, 0.4), 0);   // front, right of the axis
  EXPECT_EQ(at(3.7, 1, -1, 0.6), 3);   // right
  EXPECT_EQ(at(-1.0, -1, 1, 0.2), 1);  // rear
  EXPECT_EQ(at(-1.0, -1, 1, 0.4), 2);
  EXPECT_EQ(at(-1.0, -1, -1, 0.2), 1);
  EXPECT_EQ(at(-1.0, -1, -1, 0.4), 3);

  // Blended seams: the second camera is the one across the seam, with up
  // to half the weight right on it.
  rays.blend_angle_rad = 0.2;
  const TopViewFusion blended(DefaultRig(), kFisheyes, rays);
  const Eigen::Vector2d on_seam =
      blended.VehicleToPixel({3.7 + 2.0 * std::cos(0.49), 0.925 + 2.0 * std::sin(0.49)});
  const int u = static_cast<int>(std::lround(on_seam.x())),
            v = static_cast<int>(std::lround(on_seam.y()));
  EXPECT_EQ(blended.PrimaryCamera(u, v), 0);
  EXPECT_EQ(blended.SecondaryCamera(u, v), 2);
  EXPECT_LT(blended.PrimaryWeight(u, v), 0.6);

  TopViewOptions wrong = rays;
  wrong.seam_front_angle_rad = 1.7;
  EXPECT_THROW(TopViewFusion(DefaultRig(), kFisheyes, wrong), std::invalid_argument);
}

TEST(TopViewTest, PerturbedExtrinsicsShiftTheGround) {
  const CameraRig rig = DefaultRig();
  const CameraRig off = PerturbExtrinsics(rig, 0.02, 0.02, 7);
  const cv::Mat exact = TopViewFusion(rig, kFisheyes).Fuse(RenderAll(rig));
  const cv::Mat perturbed = TopViewFusion(off, kFisheyes).Fuse(RenderAll(rig));
  EXPECT_GT(cv::norm(exact, perturbed, cv::NORM_L1), 1000.0);
}

TEST(TopViewTest, FootprintIsMasked) {
  const CameraRig rig = DefaultRig();
  const TopViewFusion fusion(rig, kFisheyes);
  std::vector<cv::Mat> white;
  for (const std::string& name : kFisheyes) {
    const CameraIntrinsics& in = rig.Find(name)->intrinsics;
    white.emplace_back(in.height, in.width, CV_8UC1, cv::Scalar(200));
  }
  const cv::Mat top = fusion.Fuse(white);
  const Eigen::Vector2d car = fusion.VehicleToPixel({1.35, 0.0});
  EXPECT_EQ(top.at<uint8_t>(static_cast<int>(car.y()), static_cast<int>(car.x())), 0);
  const Eigen::Vector2d ground = fusion.VehicleToPixel({5.0, 3.0});
  EXPECT_EQ(top.at<uint8_t>(static_cast<int>(ground.y()), static_cast<int>(ground.x())), 200);
}

TEST(TopViewTest, WrongImageSizeNamesTheCamera) {
  const CameraRig rig = DefaultRig();
  const TopViewFusion fusion(rig, kFisheyes);
  std::vector<cv::Mat> images = RenderAll(rig);
  images[2] = cv::Mat(100, 100, CV_8UC1, cv::Scalar(0));
  try {
    fusion.Fuse(images);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'left'"), std::string::npos) << e.what();
  }
}

TEST(TopViewTest, UnknownCameraThrows) {
  EXPECT_THROW(TopViewFusion(DefaultRig(), {"front", "roof"}), std::invalid_argument);
}

}  // namespace
}  // namespace parkslam::camera
