#include "parkslam/camera/camera_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace parkslam::camera {
namespace {

CameraIntrinsics Fisheye() {
  CameraIntrinsics in;
  in.kind = CameraKind::kFisheye;
  in.fx = 180.0;
  in.fy = 182.0;
  in.distortion = {0.02, -0.005, 0.001, -0.0002};
  return in;
}

CameraIntrinsics Pinhole() {
  CameraIntrinsics in;
  in.fx = 400.0;
  in.fy = 405.0;
  in.distortion = {-0.1, 0.02, 0.001, -0.0005};
  return in;
}

void ExpectRoundTrip(const CameraModel& model) {
  int tested = 0;
  for (double u = 5; u < model.width(); u += 37) {
    for (double v = 5; v < model.height(); v += 29) {
      const auto ray = model.Unproject({u, v});
      if (!ray) continue;
      EXPECT_NEAR(ray->norm(), 1.0, 1e-12);
      const auto pixel = model.Project(*ray * 3.0);
      ASSERT_TRUE(pixel.has_value()) << u << " " << v;
      EXPECT_NEAR(pixel->x(), u, 1e-6);
      EXPECT_NEAR(pixel->y(), v, 1e-6);
      ++tested;
    }
  }
  EXPECT_GT(tested, 150);
}

TEST(CameraModelTest, FisheyeRoundTrip) { ExpectRoundTrip(CameraModel(Fisheye())); }

TEST(CameraModelTest, PinholeRoundTrip) { ExpectRoundTrip(CameraModel(Pinhole())); }

TEST(CameraModelTest, FisheyeSeesBeyondNinetyDegrees) {
  const CameraModel model(Fisheye());
  // A point 95 degrees off the axis still projects inside a 640x480 image.
  const double a = 95.0 * M_PI / 180.0;
  const auto pixel = model.Project(Eigen::Vector3d(std::sin(a), 0.0, std::cos(a)));
  ASSERT_TRUE(pixel.has_value());
  EXPECT_GT(pixel->x(), 319.5 + 180.0 * 1.5);
}

TEST(CameraModelTest, PinholeRejectsPointsBehind) {
  const CameraModel model(Pinhole());
  EXPECT_FALSE(model.Project(Eigen::Vector3d(0, 0, -1)).has_value());
  EXPECT_FALSE(model.Project(Eigen::Vector3d(100, 0, 1)).has_value());  // outside
  EXPECT_TRUE(model.Project(Eigen::Vector3d(100, 0, 1), false).has_value());
}

TEST(CameraModelTest, DefaultRigSeesTheTopViewSquareAroundTheCar) {
  const CameraRig rig = DefaultRig();
  const char* fisheyes[] = {"front", "rear", "left", "right"};
  int uncovered = 0, tested = 0;
  for (double x = 1.4 - 5.0; x <= 1.4 + 5.0; x += 0.25) {
    for (double y = -5.0; y <= 5.0; y += 0.25) {
      // The car's footprint: 4.7 m long from 1.0 m behind the rear axle.
      if (x > -1.0 && x < 3.7 && std::abs(y) < 0.925) continue;
      ++tested;
      bool seen = false;
      for (const char* name : fisheyes) {
        const CameraConfig* c = rig.Find(name);
        ASSERT_NE(c, nullptr);
        const Eigen::Vector3d p_camera = c->T_vehicle_camera.inverse() * Eigen::Vector3d(x, y, 0.0);
        seen |= CameraModel(c->intrinsics).Project(p_camera).has_value();
      }
      uncovered += !seen;
    }
  }
  EXPECT_GT(tested, 1500);
  EXPECT_EQ(uncovered, 0);
}

TEST(CameraModelTest, FrontMonoLooksForwardLevel) {
  const CameraRig rig = DefaultRig();  // alive while `mono` is used
  const CameraConfig* mono = rig.Find("front_mono");
  ASSERT_NE(mono, nullptr);
  // A point 10 m straight ahead at the camera's height lands on the centre.
  const Eigen::Vector3d p_camera =
      mono->T_vehicle_camera.inverse() * Eigen::Vector3d(11.8, 0.3, 1.3);
  const auto pixel = CameraModel(mono->intrinsics).Project(p_camera);
  ASSERT_TRUE(pixel.has_value());
  EXPECT_NEAR(pixel->x(), 639.5, 1e-9);
  EXPECT_NEAR(pixel->y(), 359.5, 1e-9);
}

// Twice the resolution, the same field of view: a ground point lands
// twice as far from the image's top-left edge; the pinhole camera stays.
TEST(CameraModelTest, FisheyeResolutionScalesPixelsNotTheView) {
  const CameraRig rig = DefaultRig();
  const CameraRig sharp = WithFisheyeResolution(rig, 2.0);
  const CameraConfig& front = *rig.Find("front");
  const CameraConfig& front2 = *sharp.Find("front");
  EXPECT_EQ(front2.intrinsics.width, 1280);
  EXPECT_EQ(front2.intrinsics.height, 960);
  EXPECT_EQ(sharp.Find("front_mono")->intrinsics.width, rig.Find("front_mono")->intrinsics.width);
  const Eigen::Vector3d p_camera =
      front.T_vehicle_camera.inverse() * Eigen::Vector3d(6.0, 1.5, 0.0);
  const auto a = CameraModel(front.intrinsics).Project(p_camera);
  const auto b = CameraModel(front2.intrinsics).Project(p_camera);
  ASSERT_TRUE(a.has_value() && b.has_value());
  EXPECT_NEAR(b->x() + 0.5, 2.0 * (a->x() + 0.5), 1e-9);
  EXPECT_NEAR(b->y() + 0.5, 2.0 * (a->y() + 0.5), 1e-9);
  EXPECT_THROW(WithFisheyeResolution(rig, 0.1), std::invalid_argument);
  EXPECT_THROW(WithFisheyeResolution(rig, std::nan("")), std::invalid_argument);
}

}  // namespace
}  // namespace parkslam::camera
