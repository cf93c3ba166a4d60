#include "parkslam/perception/camera_health.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <random>
#include <vector>

namespace parkslam::perception {
namespace {

// A 64 x 48 image of `mean` grey with sensor noise of `sigma`, new per seed.
ImagePlane Image(double mean, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(mean, sigma);
  auto pixels = std::make_shared<std::vector<std::uint8_t>>(64 * 48);
  for (auto& p : *pixels) p = static_cast<std::uint8_t>(std::clamp(noise(rng), 0.0, 255.0));
  return {64, 48, pixels};
}

CameraFrame Frame(ImagePlane front, ImagePlane left) {
  CameraFrame f;
  f.cameras = {"front", "left"};
  f.images = {std::move(front), std::move(left)};
  return f;
}

TEST(CameraHealthTest, TellsBlackAndFrozenFromNoisyLiveImages) {
  CameraHealthMonitor monitor;
  const ImagePlane stuck = Image(120, 3, 99);
  std::vector<CameraHealth> h = monitor.Check(Frame(Image(120, 3, 1), stuck));
  EXPECT_EQ(h, (std::vector<CameraHealth>{CameraHealth::kOk, CameraHealth::kOk}));
  // The same bytes again from the left camera: frozen; a dark but live
  // front image (a night scene: mean 10, noise 6) is not black.
  h = monitor.Check(Frame(Image(10, 6, 2), stuck));
  EXPECT_EQ(h, (std::vector<CameraHealth>{CameraHealth::kOk, CameraHealth::kFrozen}));
  h = monitor.Check(Frame(Image(2, 1, 3), Image(120, 3, 4)));
  EXPECT_EQ(h, (std::vector<CameraHealth>{CameraHealth::kBlack, CameraHealth::kOk}));
  EXPECT_EQ(monitor.black_images().at("front"), 1);
  EXPECT_EQ(monitor.frozen_images().at("left"), 1);
  EXPECT_EQ(monitor.black_images().count("left"), 0u);
}

}  // namespace
}  // namespace parkslam::perception
