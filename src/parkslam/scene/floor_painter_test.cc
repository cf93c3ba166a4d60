#include "parkslam/scene/floor_painter.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace parkslam::scene {
namespace {

// A bare floor (no paint, decals or verge) under even light, painted on a
// 6 m x 6 m canvas at 2 cm a pixel.
cv::Mat BareFloor(FloorMaterial material, double texture, std::uint64_t seed,
                  const std::vector<Decal>& decals = {}) {
  Scene scene;
  scene.seed = seed;
  scene.decals = decals;
  scene.floor.material = material;
  scene.floor.base = Colour(128, 128, 128);
  scene.floor.texture = texture;
  scene.floor.blotches = 0.0;
  scene.light.pools = 0.0;
  scene.light.patchy = 0.0;
  Canvas canvas(-3.0, 3.0, 6.0, 6.0, 0.02);
  PaintFloor(scene, LightMap(scene.light), FloorPainterOptions{}, nullptr, &canvas);
  cv::Mat grey;
  cv::cvtColor(canvas.bgr, grey, cv::COLOR_BGR2GRAY);
  grey.convertTo(grey, CV_32F, kRadianceScale);  // radiance in grey levels
  return grey;
}

// Median absolute difference of Gaussians at sigma and 2 sigma (pixels).
double BandEnergy(const cv::Mat& grey, double sigma_px) {
  cv::Mat a, b;
  cv::GaussianBlur(grey, a, cv::Size(), sigma_px);
  cv::GaussianBlur(grey, b, cv::Size(), 2 * sigma_px);
  cv::Mat dog = cv::abs(a - b);
  std::vector<float> v(dog.begin<float>(), dog.end<float>());
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// Between the per-pixel grain and the 0.25 m octave, worn concrete and
// asphalt show their aggregate and pores (4-10 cm); the real ps2.0 views
// carry that band, and a floor without it was one of the renderings' tells.
// With it a bare concrete floor measures 0.72 grey levels in the 3-6 cm
// band and 0.79 in the 6-12 cm one (seeds 1-3); without it, 0.24 and 0.53.
TEST(FloorPainterTest, FloorsCarryTextureAtCentimetreScales) {
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    const cv::Mat concrete = BareFloor(FloorMaterial::kConcrete, 1.0, seed);
    EXPECT_GT(BandEnergy(concrete, 1.5), 0.5) << "seed " << seed;
    EXPECT_GT(BandEnergy(concrete, 3.0), 0.65) << "seed " << seed;
    // Smooth epoxy carries less of it than concrete, and no texture none.
    const cv::Mat epoxy = BareFloor(FloorMaterial::kEpoxy, 1.0, seed);
    EXPECT_LT(BandEnergy(epoxy, 1.5), 0.5 * BandEnergy(concrete, 1.5)) << "seed " << seed;
    const cv::Mat plain = BareFloor(FloorMaterial::kConcrete, 0.0, seed);
    EXPECT_LT(BandEnergy(plain, 1.5), 0.1 * BandEnergy(concrete, 1.5)) << "seed " << seed;
  }
}

// Different scenes take different windows of the texture.
TEST(FloorPainterTest, ScenesDrawTheirOwnTexture) {
  const cv::Mat a = BareFloor(FloorMaterial::kConcrete, 1.0, 1);
  const cv::Mat b = BareFloor(FloorMaterial::kConcrete, 1.0, 2);
  EXPECT_GT(cv::norm(a, b, cv::NORM_L1) / static_cast<double>(a.total()), 0.5);
}

// The mean grey level over a disc of radius_m around p (metres on the
// 6 m canvas of BareFloor, centred on the origin).
double MeanAround(const cv::Mat& grey, const Eigen::Vector2d& p, double radius_m) {
  cv::Mat disc(grey.size(), CV_8UC1, cv::Scalar(0));
  cv::circle(
      disc,
      cv::Point(static_cast<int>((p.x() + 3.0) / 0.02), static_cast<int>((3.0 - p.y()) / 0.02)),
      static_cast<int>(radius_m / 0.02), cv::Scalar(255), -1);
  return cv::mean(grey, disc)[0];
}

// A drain grate is grey metal with dark holes, not a black hole in the
// floor: over its middle it keeps more than half the floor's brightness
// (drawn black, grates were one of the rendered views' tells).
TEST(FloorPainterTest, GratesAreGreyMetalNotBlack) {
  Decal grate;
  grate.kind = DecalKind::kGrate;
  grate.center = Eigen::Vector2d(-2.0, -2.0);  // clear of the car's own shadow
  grate.length_m = 0.8;
  grate.width_m = 0.5;
  for (const std::uint64_t seed : {1u, 2u, 3u, 4u}) {
    grate.seed = seed;
    const cv::Mat floor = BareFloor(FloorMaterial::kConcrete, 1.0, seed, {grate});
    const double inside = MeanAround(floor, grate.center, 0.15);
    const double around = MeanAround(floor, Eigen::Vector2d(-0.8, -2.0), 0.3);
    EXPECT_GT(inside, 0.5 * around) << "seed " << seed;
    EXPECT_LT(inside, 0.95 * around) << "seed " << seed;
  }
}

// A tyre mark fades in and out: at its ends it darkens the floor far less
// than in its middle, so that it never ends in a crisp crescent.
TEST(FloorPainterTest, TyreMarksFadeAtTheirEnds) {
  Decal mark;
  mark.kind = DecalKind::kTyreMark;
  mark.center = Eigen::Vector2d(0.0, -2.5);  // clear of the car's own shadow
  mark.length_m = 4.0;
  mark.width_m = 0.2;
  mark.strength = 1.0;
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    mark.seed = seed;
    const cv::Mat bare = BareFloor(FloorMaterial::kConcrete, 0.0, 1);
    const cv::Mat marked = BareFloor(FloorMaterial::kConcrete, 0.0, 1, {mark});
    // The arc runs through its centre along x, bending towards +y; its
    // ends lie about 2 m either side, a little towards the bend.
    const auto darkening = [&](const Eigen::Vector2d& p) {
      double best = 0.0;
      for (double dy = 0.0; dy <= 0.8; dy += 0.02) {
        const Eigen::Vector2d q = p + Eigen::Vector2d(0.0, dy);
        best = std::max(best, MeanAround(bare, q, 0.05) - MeanAround(marked, q, 0.05));
      }
      return best;
    };
    const double middle = darkening(Eigen::Vector2d(0.0, -2.6));
    EXPECT_GT(middle, 10.0) << "seed " << seed;
    EXPECT_LT(darkening(Eigen::Vector2d(1.95, -2.6)), 0.4 * middle) << "seed " << seed;
    EXPECT_LT(darkening(Eigen::Vector2d(-1.95, -2.6)), 0.4 * middle) << "seed " << seed;
  }
}

}  // namespace
}  // namespace parkslam::scene
