#include "parkslam/scene/scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

namespace parkslam::scene {
namespace {

TEST(SceneTest, SameSeedSameScene) {
  const Scene a = SampleScene(42), b = SampleScene(42), c = SampleScene(43);
  ASSERT_EQ(a.marks.size(), b.marks.size());
  for (size_t i = 0; i < a.marks.size(); ++i) EXPECT_EQ(a.marks[i].p_vehicle, b.marks[i].p_vehicle);
  EXPECT_EQ(a.strokes.size(), b.strokes.size());
  EXPECT_EQ(a.solids.size(), b.solids.size());
  EXPECT_FALSE(a.marks.size() == c.marks.size() && a.strokes.size() == c.strokes.size() &&
               a.solids.size() == c.solids.size() && a.floor.material == c.floor.material &&
               a.marks.front().p_vehicle == c.marks.front().p_vehicle);
}

// Over many seeds the sampler covers what the issue lists.
TEST(SceneTest, ScenesVaryOverWhatRealLotsShow) {
  std::set<int> materials, kinds, decals;
  int outdoor = 0, yellow = 0, white = 0, stencil = 0, letters = 0, l_marks = 0, t_marks = 0,
      cars = 0, perturbed = 0, night = 0, other_lines = 0;
  for (std::uint64_t seed = 0; seed < 400; ++seed) {
    const Scene s = SampleScene(seed);
    materials.insert(static_cast<int>(s.floor.material));
    outdoor += s.light.outdoor;
    night += s.light.night;
    perturbed += s.fusion_calibration > 0;
    for (const Slot& slot : s.slots) kinds.insert(static_cast<int>(slot.kind));
    for (const Decal& d : s.decals) decals.insert(static_cast<int>(d.kind));
    for (const Stroke& st : s.strokes) {
      yellow += st.paint == PaintKind::kYellow;
      white += st.paint == PaintKind::kWhite;
      other_lines += !st.slot_line;  // aisle lines (double, dashed), older layouts
    }
    for (const FloorText& t : s.texts) {
      stencil += t.stencil;
      for (char ch : t.text) letters += std::isalpha(static_cast<unsigned char>(ch)) != 0;
    }
    for (const MarkingPoint& m : s.marks) (m.is_t ? t_marks : l_marks)++;
    for (const Solid& solid : s.solids) cars += solid.material == SolidMaterial::kGlass;
  }
  EXPECT_EQ(materials.size(), 5u);
  EXPECT_EQ(kinds.size(), 3u);
  EXPECT_GE(decals.size(), 12u);
  EXPECT_GT(outdoor, 100);
  EXPECT_LT(outdoor, 300);
  EXPECT_GT(night, 5);
  EXPECT_GT(perturbed, 100);
  EXPECT_GT(yellow, 100);
  EXPECT_GT(white, yellow);
  EXPECT_GT(stencil, 50);
  EXPECT_GT(letters, 100);
  EXPECT_GT(l_marks, 50);
  EXPECT_GT(t_marks, 5 * l_marks);
  EXPECT_GT(cars, 300);
  EXPECT_GT(other_lines, 400);
}

TEST(SceneTest, SlotsJoinNeighbouringMarksAndLieToTheLeftOfTheirEntrance) {
  for (std::uint64_t seed = 0; seed < 50; ++seed) {
    const Scene s = SampleScene(seed);
    for (const Slot& slot : s.slots) {
      const MarkingPoint& a = s.marks[static_cast<size_t>(slot.a)];
      const MarkingPoint& b = s.marks[static_cast<size_t>(slot.b)];
      const Eigen::Vector2d entrance = b.p_vehicle - a.p_vehicle;
      EXPECT_GT(entrance.norm(), 2.0);
      EXPECT_LT(entrance.norm(), 7.5);
      // The slot's interior (along the separating lines) lies to the left.
      const Eigen::Vector2d left(-entrance.y(), entrance.x());
      EXPECT_GT(left.dot(a.direction), 0.0) << "seed " << seed;
      EXPECT_NEAR(a.direction.norm(), 1.0, 1e-9);
    }
  }
}

TEST(SceneTest, SolidsKeepOffTheCar) {
  for (std::uint64_t seed = 0; seed < 200; ++seed) {
    for (const Solid& solid : SampleScene(seed).solids) {
      if (solid.shape != SolidShape::kBox || solid.half_x > 5) continue;
      const bool inside =
          solid.center.x() > -1.0 && solid.center.x() < 3.7 && std::abs(solid.center.y()) < 0.925;
      EXPECT_FALSE(inside) << "seed " << seed;
    }
  }
}

// The unit's sensor and lookup shares: 0 and 1 mean none and all, and a
// nearest share of 0 changes nothing else (it is drawn last).
TEST(SceneTest, SensorAndLookupSharesPickTheUnits) {
  SceneSamplerOptions sharp;
  sharp.coarse_sensor_share = 0.0;
  sharp.nearest_lookup_share = 1.0;
  SceneSamplerOptions half;
  half.nearest_lookup_share = 0.5;
  int nearest_by_default = 0, coarse_by_default = 0, nearest_half = 0;
  for (std::uint64_t seed = 0; seed < 200; ++seed) {
    const Scene plain = SampleScene(seed), s = SampleScene(seed, sharp);
    const Scene h = SampleScene(seed, half);
    nearest_by_default += plain.fusion_nearest;
    coarse_by_default += plain.cameras.front().sensor_scale < 1.0;
    EXPECT_TRUE(s.fusion_nearest);
    EXPECT_EQ(s.cameras.front().sensor_scale, 1.0);
    nearest_half += h.fusion_nearest;
    EXPECT_EQ(h.saturation, plain.saturation);
    EXPECT_EQ(h.cameras.back().seed, plain.cameras.back().seed);
  }
  EXPECT_EQ(nearest_by_default, 0);
  EXPECT_GT(coarse_by_default, 90);  // 0.6 of 200
  EXPECT_LT(coarse_by_default, 150);
  EXPECT_GT(nearest_half, 70);
  EXPECT_LT(nearest_half, 130);
  SceneSamplerOptions wrong;
  wrong.nearest_lookup_share = -0.1;
  std::string error;
  EXPECT_FALSE(wrong.IsValid(&error));
  EXPECT_NE(error.find("nearest_lookup_share"), std::string::npos);
}

// Straight seams: a share of 0 (the default) leaves every scene as it was,
// 1 gives every unit one of the straight layouts (after the others), and
// the draw changes nothing else.
TEST(SceneTest, RaySeamShareAddsStraightLayoutsLast) {
  SceneSamplerOptions all;
  all.ray_seam_share = 1.0;
  SceneSamplerOptions half;
  half.ray_seam_share = 0.5;
  int straight_half = 0;
  std::vector<int> layouts(6, 0);
  for (std::uint64_t seed = 0; seed < 200; ++seed) {
    const Scene plain = SampleScene(seed), s = SampleScene(seed, all), h = SampleScene(seed, half);
    EXPECT_GE(plain.fusion_seams, 0);
    EXPECT_LT(plain.fusion_seams, 3);
    ASSERT_GE(s.fusion_seams, 3);
    ASSERT_LT(s.fusion_seams, 6);
    ++layouts[static_cast<size_t>(s.fusion_seams)];
    straight_half += h.fusion_seams >= 3;
    if (h.fusion_seams < 3) {
      EXPECT_EQ(h.fusion_seams, plain.fusion_seams);
    }
    EXPECT_EQ(s.saturation, plain.saturation);
    EXPECT_EQ(s.fusion_nearest, plain.fusion_nearest);
    EXPECT_EQ(s.cameras.back().seed, plain.cameras.back().seed);
  }
  for (int l = 3; l < 6; ++l) EXPECT_GT(layouts[static_cast<size_t>(l)], 40) << "layout " << l;
  EXPECT_GT(straight_half, 70);
  EXPECT_LT(straight_half, 130);
  SceneSamplerOptions wrong;
  wrong.ray_seam_share = 1.5;
  std::string error;
  EXPECT_FALSE(wrong.IsValid(&error));
  EXPECT_NE(error.find("ray_seam_share"), std::string::npos);
}

// Chroma noise: a share of 0 (the default) leaves every scene as it was;
// 1 gives every fisheye of the unit some, near one amplitude per unit.
TEST(SceneTest, ChromaNoiseShareGivesTheUnitsColourNoise) {
  SceneSamplerOptions all;
  all.chroma_noise_share = 1.0;
  for (std::uint64_t seed = 0; seed < 50; ++seed) {
    const Scene plain = SampleScene(seed), s = SampleScene(seed, all);
    ASSERT_EQ(s.cameras.size(), plain.cameras.size());
    double lo = 1e9, hi = 0.0;
    for (size_t c = 0; c < s.cameras.size(); ++c) {
      EXPECT_EQ(plain.cameras[c].chroma_noise, 0.0);
      lo = std::min(lo, s.cameras[c].chroma_noise);
      hi = std::max(hi, s.cameras[c].chroma_noise);
      EXPECT_EQ(s.cameras[c].seed, plain.cameras[c].seed);
    }
    EXPECT_GE(lo, 0.3 * 0.8 * all.chroma_noise_max);
    EXPECT_LE(hi, 1.2 * all.chroma_noise_max);
    EXPECT_LE(hi, lo * 1.5 + 1e-9);  // one unit, cameras within 0.8-1.2 of its amplitude
    EXPECT_EQ(s.fusion_seams, plain.fusion_seams);
  }
  SceneSamplerOptions wrong;
  wrong.chroma_noise_share = 2.0;
  std::string error;
  EXPECT_FALSE(wrong.IsValid(&error));
  EXPECT_NE(error.find("chroma_noise_share"), std::string::npos);
}

TEST(SceneTest, RejectsInvalidOptions) {
  SceneSamplerOptions options;
  options.outdoor_probability = 1.5;
  EXPECT_THROW(SampleScene(1, options), std::invalid_argument);
  std::string error;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("outdoor_probability"), std::string::npos);
}

}  // namespace
}  // namespace parkslam::scene
