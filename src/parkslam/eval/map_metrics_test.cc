#include "parkslam/eval/map_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "parkslam/common/angles.h"
#include "parkslam/common/random.h"

namespace parkslam::eval {
namespace {

constexpr double kSlotWidthM = 2.5;
constexpr double kSlotDepthM = 5.3;
constexpr double kAisleWidthM = 6.0;
constexpr int kSlotsPerRow = 12;

// A slot from its entrance corners 0 and 1; the slot lies on the left of the
// walk from corner 0 to corner 1, so 0-1-2-3 goes round counter-clockwise.
MapSlot Slot(const std::string& id, const Eigen::Vector2d& c0, const Eigen::Vector2d& c1,
             double depth_m, SlotKind kind = SlotKind::kPerpendicular) {
  const Eigen::Vector2d along = (c1 - c0).normalized();
  const Eigen::Vector2d left(-along.y(), along.x());
  MapSlot slot;
  slot.id = id;
  slot.kind = kind;
  slot.corners_map = {c0, c1, c1 + depth_m * left, c0 + depth_m * left};
  return slot;
}

// row_pairs pairs of perpendicular rows facing each other across a 6 m aisle
// (12 slots of 2.5 x 5.3 m a row; pairs back to back), 4 parallel slots of
// 6 x 2.5 m along the western aisle, and 6 tags on the northern wall. IDs
// "1", "2", ... in that order, all painted and legible.
SemanticMap MakeLot(int row_pairs = 1) {
  SemanticMap lot;
  int next_id = 1;
  const double pair_height_m = 2.0 * kSlotDepthM + kAisleWidthM;
  for (int pair = 0; pair < row_pairs; ++pair) {
    const double south_entrance_y = pair * pair_height_m + kSlotDepthM;
    const double north_entrance_y = south_entrance_y + kAisleWidthM;
    for (int k = 0; k < kSlotsPerRow; ++k) {  // south row, open to the north
      const double x = k * kSlotWidthM;
      lot.slots.push_back(Slot(std::to_string(next_id++), {x + kSlotWidthM, south_entrance_y},
                               {x, south_entrance_y}, kSlotDepthM));
    }
    for (int k = 0; k < kSlotsPerRow; ++k) {  // north row, open to the south
      const double x = k * kSlotWidthM;
      lot.slots.push_back(Slot(std::to_string(next_id++), {x, north_entrance_y},
                               {x + kSlotWidthM, north_entrance_y}, kSlotDepthM));
    }
  }
  for (int k = 0; k < 4; ++k) {  // parallel, open to the east
    const double y = 6.0 * k;
    lot.slots.push_back(
        Slot(std::to_string(next_id++), {-6.0, y}, {-6.0, y + 6.0}, 2.5, SlotKind::kParallel));
  }
  const double wall_y = row_pairs * pair_height_m + 0.4;
  for (int k = 0; k < 6; ++k) {
    MapTag tag;
    tag.tag_id = k + 1;
    tag.p_map = Eigen::Vector2d(2.0 + 6.0 * k, wall_y);
    tag.yaw_map_rad = -kPi / 2.0;
    lot.tags.push_back(tag);
  }
  return lot;
}

SemanticMap Transformed(const SE2& T_new_old, SemanticMap map) {
  for (MapSlot& slot : map.slots) {
    for (Eigen::Vector2d& corner : slot.corners_map) corner = T_new_old * corner;
  }
  for (MapTag& tag : map.tags) {
    tag.p_map = T_new_old * tag.p_map;
    tag.yaw_map_rad = NormalizeAngle(tag.yaw_map_rad + T_new_old.yaw());
  }
  return map;
}

MapSlot Shifted(MapSlot slot, const Eigen::Vector2d& offset_m) {
  for (Eigen::Vector2d& corner : slot.corners_map) corner += offset_m;
  return slot;
}

void MakeTemporary(MapSlot* slot, int number) {
  slot->id = std::to_string(number);
  slot->id.insert(slot->id.begin(), 't');  // "t<n>"
  slot->temporary = true;
}

MapMetricsOptions Unaligned() {
  MapMetricsOptions options;
  options.align = false;
  return options;
}

MapMetricsOptions WithRadius(double match_radius_m) {
  MapMetricsOptions options;
  options.match_radius_m = match_radius_m;
  return options;
}

void ExpectIdentity(const SE2& T) {
  EXPECT_NEAR(T.x(), 0.0, 1e-9);
  EXPECT_NEAR(T.y(), 0.0, 1e-9);
  EXPECT_NEAR(T.yaw(), 0.0, 1e-12);
}

TEST(EvaluateMapTest, TruthAgainstItselfMatchesEverything) {
  const SemanticMap truth = MakeLot();
  const MapMetrics m = EvaluateMap(truth, truth);
  EXPECT_EQ(m.slots_true, 28);
  EXPECT_EQ(m.slots_matched, 28);
  EXPECT_EQ(m.slots_missed, 0);
  EXPECT_EQ(m.slots_spurious, 0);
  EXPECT_EQ(m.slots_duplicate, 0);
  EXPECT_NEAR(m.slot_corner_rmse_m, 0.0, 1e-9);
  EXPECT_NEAR(m.slot_corner_max_m, 0.0, 1e-9);
  EXPECT_DOUBLE_EQ(m.id_accuracy, 1.0);
  EXPECT_DOUBLE_EQ(m.temporary_id_share, 0.0);
  EXPECT_EQ(m.tags_true, 6);
  EXPECT_EQ(m.tags_matched, 6);
  EXPECT_NEAR(m.tag_rmse_m, 0.0, 1e-9);
  EXPECT_EQ(m.tags_not_in_truth, 0);
  ExpectIdentity(m.T_truth_map);
}

TEST(EvaluateMapTest, RotatedShiftedNoisyMapIsAlignedBack) {
  const SemanticMap truth = MakeLot();
  const SE2 T_map_truth(100.0, -50.0, DegToRad(30.0));
  SemanticMap map = Transformed(T_map_truth, truth);
  Random rng(7);
  double noise_squared_sum = 0.0;
  for (MapSlot& slot : map.slots) {
    for (Eigen::Vector2d& corner : slot.corners_map) {
      const Eigen::Vector2d noise(rng.Gaussian(0.02), rng.Gaussian(0.02));
      corner += noise;
      noise_squared_sum += noise.squaredNorm();
    }
  }
  for (MapTag& tag : map.tags) tag.p_map += Eigen::Vector2d(rng.Gaussian(0.02), rng.Gaussian(0.02));
  const double noise_rms_m = std::sqrt(noise_squared_sum / (4.0 * 28.0));

  const MapMetrics m = EvaluateMap(map, truth);
  EXPECT_EQ(m.slots_matched, 28);
  EXPECT_EQ(m.slots_spurious, 0);
  EXPECT_EQ(m.slots_duplicate, 0);
  EXPECT_DOUBLE_EQ(m.id_accuracy, 1.0);
  // 2 cm a coordinate is 2.8 cm a corner; the 3-dof fit absorbs a little.
  EXPECT_NEAR(m.slot_corner_rmse_m, noise_rms_m, 0.002);
  EXPECT_GT(m.slot_corner_rmse_m, 0.02);
  EXPECT_LT(m.slot_corner_rmse_m, 0.035);
  EXPECT_GT(m.slot_corner_max_m, m.slot_corner_rmse_m);
  EXPECT_LT(m.slot_corner_max_m, 0.12);
  EXPECT_EQ(m.tags_matched, 6);
  EXPECT_LT(m.tag_rmse_m, 0.08);
  // The alignment undoes the transform: near identity over the lot.
  const SE2 residual = m.T_truth_map * T_map_truth;
  EXPECT_LT(residual.translation().norm(), 0.02);
  EXPECT_LT(std::abs(residual.yaw()), DegToRad(0.1));
}

TEST(EvaluateMapTest, WithoutAlignmentAShiftedMapMatchesNothing) {
  const SemanticMap truth = MakeLot();
  const MapMetrics m = EvaluateMap(Transformed(SE2(100.0, -50.0, 0.5), truth), truth, Unaligned());
  EXPECT_EQ(m.slots_matched, 0);
  EXPECT_EQ(m.slots_missed, 28);
  EXPECT_EQ(m.slots_spurious, 28);
  ExpectIdentity(m.T_truth_map);
}

TEST(EvaluateMapTest, WrongIdsDoNotSpoilTheInitialAlignment) {
  const SemanticMap truth = MakeLot();
  const SE2 T_map_truth(-20.0, 35.0, DegToRad(-120.0));
  SemanticMap map = Transformed(T_map_truth, truth);
  // 5 of 28 slots swap IDs with a slot far away: 10 wrong correspondences.
  for (int k = 0; k < 5; ++k) std::swap(map.slots[k].id, map.slots[27 - k].id);
  map.tags.clear();
  const MapMetrics m = EvaluateMap(map, truth);
  EXPECT_EQ(m.slots_matched, 28);
  EXPECT_NEAR(m.slot_corner_rmse_m, 0.0, 1e-6);
  EXPECT_NEAR(m.id_accuracy, 18.0 / 28.0, 1e-12);
}

TEST(EvaluateMapTest, ManyCorrespondencesAreSubsampledAndStillAligned) {
  const SemanticMap truth = MakeLot(10);  // 244 slots, above the 200 of all pairs
  ASSERT_EQ(truth.slots.size(), 244u);
  const SE2 T_map_truth(3.0, -7.0, DegToRad(75.0));
  const MapMetrics m = EvaluateMap(Transformed(T_map_truth, truth), truth);
  EXPECT_EQ(m.slots_matched, 244);
  EXPECT_EQ(m.slots_spurious, 0);
  EXPECT_NEAR(m.slot_corner_rmse_m, 0.0, 1e-6);
}

TEST(EvaluateMapTest, RemovedSlotIsMissed) {
  const SemanticMap truth = MakeLot();
  SemanticMap map = truth;
  map.slots.erase(map.slots.begin() + 7);
  const MapMetrics m = EvaluateMap(map, truth);
  EXPECT_EQ(m.slots_true, 28);
  EXPECT_EQ(m.slots_matched, 27);
  EXPECT_EQ(m.slots_missed, 1);
  EXPECT_EQ(m.slots_spurious, 0);
  EXPECT_EQ(m.slots_duplicate, 0);
}

TEST(EvaluateMapTest, FarExtraSlotIsSpurious) {
  const SemanticMap truth = MakeLot();
  SemanticMap map = truth;
  map.slots.push_back(Slot("99", {80.0, 80.0}, {82.5, 80.0}, kSlotDepthM));
  const MapMetrics m = EvaluateMap(map, truth);
  EXPECT_EQ(m.slots_matched, 28);
  EXPECT_EQ(m.slots_spurious, 1);
  EXPECT_EQ(m.slots_duplicate, 0);
  EXPECT_NEAR(m.slot_corner_rmse_m, 0.0, 1e-9);
}

TEST(EvaluateMapTest, SlotCopiedNearbyIsDuplicate) {
  const SemanticMap truth = MakeLot();
  SemanticMap map = truth;
  MapSlot copy = Shifted(truth.slots[3], {0.3, 0.0});
  MakeTemporary(&copy, 1);
  map.slots.push_back(copy);
  const MapMetrics m = EvaluateMap(map, truth);
  EXPECT_EQ(m.slots_matched, 28);
  EXPECT_EQ(m.slots_duplicate, 1);
  EXPECT_EQ(m.slots_spurious, 0);
  EXPECT_DOUBLE_EQ(m.id_accuracy, 1.0);  // the original, nearer, is the match
}

// The per-slot verdicts say what the counts say, slot by slot.
TEST(EvaluateMapTest, VerdictsNameEachMapSlot) {
  const SemanticMap truth = MakeLot();
  SemanticMap map = truth;
  map.slots.erase(map.slots.begin() + 7);                                    // truth 7 missed
  std::swap(map.slots[4].id, map.slots[5].id);                               // two wrong IDs
  for (Eigen::Vector2d& c : map.slots[2].corners_map) c.y() += 0.2;          // one off by 0.2 m
  map.slots.push_back(Slot("99", {80.0, 80.0}, {82.5, 80.0}, kSlotDepthM));  // spurious
  MapSlot copy = Shifted(truth.slots[3], {0.3, 0.0});
  MakeTemporary(&copy, 1);
  map.slots.push_back(copy);  // duplicate of truth 3
  const MapMetrics m = EvaluateMap(map, truth, Unaligned());
  ASSERT_EQ(m.map_slots.size(), map.slots.size());
  EXPECT_EQ(m.missed_truth_slots, std::vector<int>{7});
  int matched = 0, wrong_ids = 0;
  for (const MapSlotVerdict& v : m.map_slots) {
    matched += v.verdict == SlotVerdict::kMatched;
    wrong_ids += v.verdict == SlotVerdict::kMatched && !v.id_right;
  }
  EXPECT_EQ(matched, m.slots_matched);
  EXPECT_EQ(wrong_ids, 2);
  EXPECT_NEAR(m.map_slots[2].corner_rms_m, 0.2, 1e-9);
  EXPECT_NEAR(m.map_slots[3].corner_rms_m, 0.0, 1e-9);
  EXPECT_EQ(m.map_slots[map.slots.size() - 2].verdict, SlotVerdict::kSpurious);
  EXPECT_EQ(m.map_slots.back().verdict, SlotVerdict::kDuplicate);
  EXPECT_EQ(m.map_slots.back().truth_slot, 3);
}

TEST(EvaluateMapTest, MatchRadiusIsTheThreshold) {
  const SemanticMap truth = MakeLot();
  const MapMetricsOptions options = Unaligned();
  ASSERT_EQ(options.match_radius_m, 1.0);
  // Slot 2 moved into the aisle, just inside and just outside the radius.
  SemanticMap inside = truth;
  for (Eigen::Vector2d& c : inside.slots[2].corners_map) c.y() += 0.95;
  const MapMetrics m_inside = EvaluateMap(inside, truth, options);
  EXPECT_EQ(m_inside.slots_matched, 28);
  EXPECT_NEAR(m_inside.slot_corner_max_m, 0.95, 1e-9);

  SemanticMap outside = truth;
  for (Eigen::Vector2d& c : outside.slots[2].corners_map) c.y() += 1.05;
  const MapMetrics m_outside = EvaluateMap(outside, truth, options);
  EXPECT_EQ(m_outside.slots_matched, 27);
  EXPECT_EQ(m_outside.slots_missed, 1);
  EXPECT_EQ(m_outside.slots_spurious, 1);
}

TEST(EvaluateMapTest, SwappedIdPairLowersIdAccuracyByTwoOverN) {
  const SemanticMap truth = MakeLot();
  SemanticMap map = truth;
  std::swap(map.slots[4].id, map.slots[5].id);
  const MapMetrics m = EvaluateMap(map, truth);
  EXPECT_EQ(m.slots_matched, 28);
  EXPECT_NEAR(m.id_accuracy, 1.0 - 2.0 / 28.0, 1e-12);
  EXPECT_NEAR(m.slot_corner_rmse_m, 0.0, 1e-9);
}

TEST(EvaluateMapTest, TemporaryIdsWhereTheTruthIdIsIllegibleAreRight) {
  SemanticMap truth = MakeLot();
  truth.slots[5].id_legible = false;
  truth.slots[9].id_legible = false;
  truth.slots[20].id.clear();  // no painted ID at all
  SemanticMap map = MakeLot();
  MakeTemporary(&map.slots[5], 1);
  MakeTemporary(&map.slots[9], 2);
  MakeTemporary(&map.slots[20], 3);
  const MapMetrics m = EvaluateMap(map, truth);
  EXPECT_DOUBLE_EQ(m.id_accuracy, 1.0);
  EXPECT_NEAR(m.temporary_id_share, 3.0 / 28.0, 1e-12);
}

TEST(EvaluateMapTest, PaintedIdReadRightWhereTheTruthCallsThePaintWornIsRight) {
  SemanticMap truth = MakeLot();
  truth.slots[5].id_legible = false;
  truth.slots[9].id_legible = false;
  SemanticMap map = MakeLot();
  map.slots[9].id = "77";  // misread worn paint is still wrong
  const MapMetrics m = EvaluateMap(map, truth);
  EXPECT_NEAR(m.id_accuracy, 27.0 / 28.0, 1e-12);
  EXPECT_EQ(m.ids_worn_read, 1);
  EXPECT_TRUE(m.map_slots[5].id_right);
  EXPECT_TRUE(m.map_slots[5].id_worn_read);
  EXPECT_FALSE(m.map_slots[9].id_right);
  EXPECT_FALSE(m.map_slots[4].id_worn_read);
}

TEST(EvaluateMapTest, ObservedAndGuessedCornersAreScoredApartAgainstTheirSigmas) {
  const SemanticMap truth = MakeLot();
  SemanticMap map = truth;
  // Every slot's entrance corners seen (sigma 2 cm), the far ones guessed
  // (sigma 10 cm). Slot 0's far corners lie 0.3 m too deep: outside their
  // 2 sigma (0.249 m); slot 1's 0.2 m: inside. Slot 2's entrance corner 0
  // is 6 cm off: outside its 2 sigma (0.0497 m).
  for (MapSlot& slot : map.slots) {
    slot.corner_observed = {true, true, false, false};
    slot.corner_sigma_m = {0.02, 0.02, 0.1, 0.1};
  }
  const auto deepen = [](MapSlot* slot, double by_m) {
    const Eigen::Vector2d inward = (slot->corners_map[3] - slot->corners_map[0]).normalized();
    slot->corners_map[2] += by_m * inward;
    slot->corners_map[3] += by_m * inward;
  };
  deepen(&map.slots[0], 0.3);
  deepen(&map.slots[1], 0.2);
  map.slots[2].corners_map[0] += Eigen::Vector2d(0.06, 0.0);
  MapMetricsOptions options;
  options.align = false;
  const MapMetrics m = EvaluateMap(map, truth, options);
  ASSERT_EQ(m.slots_matched, 28);
  EXPECT_EQ(m.observed_corners.count, 56);
  EXPECT_EQ(m.unobserved_corners.count, 56);
  EXPECT_NEAR(m.observed_corners.rmse_m, std::sqrt(0.06 * 0.06 / 56), 1e-9);
  EXPECT_NEAR(m.observed_corners.max_m, 0.06, 1e-9);
  EXPECT_NEAR(m.observed_corners.within_2sigma, 55.0 / 56.0, 1e-12);
  EXPECT_NEAR(m.unobserved_corners.rmse_m, std::sqrt((2 * 0.09 + 2 * 0.04) / 56), 1e-9);
  EXPECT_NEAR(m.unobserved_corners.max_m, 0.3, 1e-9);
  EXPECT_NEAR(m.unobserved_corners.within_2sigma, 54.0 / 56.0, 1e-12);
  EXPECT_NEAR(m.map_slots[0].corner_error_m[2], 0.3, 1e-9);
  EXPECT_NEAR(m.map_slots[2].corner_error_m[0], 0.06, 1e-9);
}

TEST(EvaluateMapTest, TemporaryIdWhereTheTruthIdIsLegibleIsWrong) {
  const SemanticMap truth = MakeLot();
  SemanticMap map = truth;
  MakeTemporary(&map.slots[11], 1);
  const MapMetrics m = EvaluateMap(map, truth);
  EXPECT_NEAR(m.id_accuracy, 27.0 / 28.0, 1e-12);
  EXPECT_NEAR(m.temporary_id_share, 1.0 / 28.0, 1e-12);
}

TEST(EvaluateMapTest, MaskCountsOnlyMaskedTruthSlots) {
  const SemanticMap truth = MakeLot();
  MapMetricsOptions options;
  options.truth_slot_mask.assign(28, false);
  for (int k = 0; k < kSlotsPerRow; ++k) options.truth_slot_mask[k] = true;  // south row
  SemanticMap map = truth;
  // Outside the mask: a wrong ID, a duplicate, and a missing slot.
  std::swap(map.slots[12].id, map.slots[13].id);
  map.slots.push_back(Shifted(truth.slots[14], {0.3, 0.0}));
  map.slots.erase(map.slots.begin() + 15);
  const MapMetrics m = EvaluateMap(map, truth, options);
  EXPECT_EQ(m.slots_true, 12);
  EXPECT_EQ(m.slots_matched, 12);
  EXPECT_EQ(m.slots_missed, 0);
  EXPECT_EQ(m.slots_spurious, 0);
  EXPECT_EQ(m.slots_duplicate, 0);
  EXPECT_DOUBLE_EQ(m.id_accuracy, 1.0);
}

TEST(EvaluateMapTest, MaskOfTheWrongSizeThrows) {
  const SemanticMap truth = MakeLot();
  MapMetricsOptions options;
  options.truth_slot_mask.assign(27, true);
  EXPECT_THROW(EvaluateMap(truth, truth, options), std::invalid_argument);
  options.truth_slot_mask.assign(29, true);
  EXPECT_THROW(EvaluateMap(truth, truth, options), std::invalid_argument);
}

TEST(EvaluateMapTest, NonPositiveMatchRadiusThrows) {
  const SemanticMap truth = MakeLot();
  EXPECT_THROW(EvaluateMap(truth, truth, WithRadius(0.0)), std::invalid_argument);
  EXPECT_THROW(EvaluateMap(truth, truth, WithRadius(-1.0)), std::invalid_argument);
  EXPECT_THROW(EvaluateMap(truth, truth, WithRadius(std::numeric_limits<double>::quiet_NaN())),
               std::invalid_argument);
  EXPECT_NO_THROW(EvaluateMap(truth, truth, WithRadius(0.01)));
}

TEST(EvaluateMapTest, EmptyMapMissesEverythingWithoutNan) {
  const SemanticMap truth = MakeLot();
  const MapMetrics m = EvaluateMap(SemanticMap{}, truth);
  EXPECT_EQ(m.slots_true, 28);
  EXPECT_EQ(m.slots_matched, 0);
  EXPECT_EQ(m.slots_missed, 28);
  EXPECT_EQ(m.slots_spurious, 0);
  EXPECT_EQ(m.slot_corner_rmse_m, 0.0);
  EXPECT_EQ(m.slot_corner_max_m, 0.0);
  EXPECT_EQ(m.id_accuracy, 0.0);
  EXPECT_EQ(m.temporary_id_share, 0.0);
  EXPECT_EQ(m.tags_true, 6);
  EXPECT_EQ(m.tags_matched, 0);
  EXPECT_EQ(m.tag_rmse_m, 0.0);
  ExpectIdentity(m.T_truth_map);
}

TEST(EvaluateMapTest, CountsMapTagsTheLotNoLongerHas) {
  SemanticMap truth = MakeLot();
  const SemanticMap map = truth;
  truth.tags.erase(truth.tags.begin() + 2);  // taken down since the map was made
  const MapMetrics m = EvaluateMap(map, truth);
  EXPECT_EQ(m.tags_true, 5);
  EXPECT_EQ(m.tags_matched, 5);
  EXPECT_EQ(m.tags_not_in_truth, 1);
}

TEST(EvaluateMapTest, EmptyTruthMakesEveryMapSlotSpurious) {
  const MapMetrics m = EvaluateMap(MakeLot(), SemanticMap{});
  EXPECT_EQ(m.slots_true, 0);
  EXPECT_EQ(m.slots_spurious, 28);
  EXPECT_EQ(m.id_accuracy, 0.0);
}

TEST(EvaluateMapTest, MapWithoutIdsFallsBackToIdentityAndStillMatches) {
  const SemanticMap truth = MakeLot();
  SemanticMap map = truth;
  for (std::size_t i = 0; i < map.slots.size(); ++i) {
    MakeTemporary(&map.slots[i], static_cast<int>(i));
  }
  map.tags.clear();
  const MapMetrics m = EvaluateMap(map, truth);
  EXPECT_EQ(m.slots_matched, 28);
  EXPECT_NEAR(m.slot_corner_rmse_m, 0.0, 1e-9);
  ExpectIdentity(m.T_truth_map);
  EXPECT_DOUBLE_EQ(m.temporary_id_share, 1.0);
}

TEST(EvaluateMapTest, MapWithoutIdsSlightlyOffIsRefinedOnItsSlots) {
  const SemanticMap truth = MakeLot();
  SemanticMap map = Transformed(SE2(0.3, -0.2, 0.0), truth);
  for (std::size_t i = 0; i < map.slots.size(); ++i) {
    MakeTemporary(&map.slots[i], static_cast<int>(i));
  }
  map.tags.clear();
  const MapMetrics m = EvaluateMap(map, truth);
  EXPECT_EQ(m.slots_matched, 28);
  EXPECT_NEAR(m.slot_corner_rmse_m, 0.0, 1e-9);
  EXPECT_NEAR(m.T_truth_map.x(), -0.3, 1e-9);
  EXPECT_NEAR(m.T_truth_map.y(), 0.2, 1e-9);
}

TEST(EvaluateMapTest, TagsMatchById) {
  const SemanticMap truth = MakeLot();
  SemanticMap map = truth;
  map.tags.erase(map.tags.begin() + 2);  // ID 3 not mapped
  map.tags[0].p_map.x() += 0.1;
  MapTag unknown;  // not in the truth
  unknown.tag_id = 42;
  unknown.p_map = Eigen::Vector2d(50.0, 50.0);
  map.tags.push_back(unknown);
  const MapMetrics m = EvaluateMap(map, truth, Unaligned());
  EXPECT_EQ(m.tags_true, 6);
  EXPECT_EQ(m.tags_matched, 5);
  EXPECT_NEAR(m.tag_rmse_m, std::sqrt(0.01 / 5.0), 1e-12);
}

}  // namespace
}  // namespace parkslam::eval
