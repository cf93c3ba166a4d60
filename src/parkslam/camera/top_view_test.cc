#include "parkslam/camera/top_view.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <cmath>

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

class TopViewLookupTest : public ::testing::TestWithParam<FusionLookup> {};

TEST_P(TopViewLookupTest, GroundPointsLandAtTheirPredictedPixels) {
  const CameraRig rig = DefaultRig();
  const TopViewFusion fusion(rig, kFisheyes);
  const cv::Mat top = fusion.Fuse(RenderAll(rig), GetParam());
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
  EXPECT_LT(worst, GetParam() == FusionLookup::kBilinear ? 1.0 : 1.5);
  EXPECT_LT((bias / checked).norm(), 0.15) << (bias / checked).transpose();
}

INSTANTIATE_TEST_SUITE_P(BothLookups, TopViewLookupTest,
                         ::testing::Values(FusionLookup::kBilinear, FusionLookup::kNearest));

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
