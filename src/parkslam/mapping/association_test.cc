#include "parkslam/mapping/association.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "parkslam/mapping/mapping_parts_test_util.h"
#include "parkslam/mapping/slot_management.h"

namespace parkslam::mapping {
namespace {

using test_util::SlotAt;
using test_util::StateWithOneKeyframe;

constexpr double kSigma_m = 0.05;

TEST(AssociationTest, PlausibleSlotsOnly) {
  EXPECT_TRUE(PlausibleSlot(SlotAt(0, 0)));
  SlotObservation flat = SlotAt(0, 0);
  flat.corners_vehicle[3] = {5.3, 0.5};  // about 5 degrees from the entrance
  EXPECT_FALSE(PlausibleSlot(flat));
  SlotObservation short_entrance = SlotAt(0, 0);
  short_entrance.corners_vehicle[1] = {0.3, 0.0};
  EXPECT_FALSE(PlausibleSlot(short_entrance));
  SlotObservation nan = SlotAt(0, 0);
  nan.corners_vehicle[2].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(PlausibleSlot(nan));
  EXPECT_NEAR(SlotAngle(SlotAt(0, 0)), M_PI / 2, 1e-12);
}

TEST(AssociationTest, CornerSigmaHasAFloorAndGuessedCornersAreLoose) {
  MapperOptions options;
  SlotObservation obs = SlotAt(0, 0);
  obs.corner_sigma_m = 1e-4;
  EXPECT_EQ(CornerSigma(obs, 0, options), options.min_corner_sigma_m);
  EXPECT_EQ(CornerSigma(obs, 3, options), options.guessed_corner_sigma_m);
}

TEST(AssociationTest, AnEmptyMapMakesANewSlot) {
  const MapState state = StateWithOneKeyframe();
  EXPECT_TRUE(AssociateSlot(state, 0, SlotAt(3, 2, "12"), kSigma_m, MapperOptions{}).new_slot);
}

TEST(AssociationTest, ANeighbourIsACandidateBesideTheNullHypothesis) {
  MapperOptions options;
  MapState state = StateWithOneKeyframe();
  CreateSlot(&state, 0, SlotAt(3, 2), options);
  CreateSlot(&state, 0, SlotAt(30, 2), options);
  const SlotAssociation a = AssociateSlot(state, 0, SlotAt(3.05, 2.0), kSigma_m, options);
  ASSERT_FALSE(a.new_slot);
  ASSERT_EQ(a.record.candidates.size(), 1u);
  EXPECT_EQ(a.record.candidates[0], 0);
  EXPECT_EQ(a.record.chosen, 0);
  EXPECT_TRUE(a.record.has_null);
  EXPECT_DOUBLE_EQ(a.record.weights[0], options.geometry_weight);
  // 2.5 m off (beyond nn_search_radius_m) and no ID: a new slot.
  EXPECT_TRUE(AssociateSlot(state, 0, SlotAt(5.5, 2.0), kSigma_m, options).new_slot);
}

TEST(AssociationTest, AnAgreeingIdReachesFartherThanTheNeighbourGate) {
  MapperOptions options;
  MapState state = StateWithOneKeyframe();
  CreateSlot(&state, 0, SlotAt(3, 2, "123"), options);
  // 3 m away: beyond the neighbour gate, within id_search_radius_m, after a
  // long drive since the last solve (the prediction 2 m uncertain).
  const double drifted_m = 2.0;
  const SlotAssociation same = AssociateSlot(state, 0, SlotAt(6, 2, "123"), drifted_m, options);
  ASSERT_FALSE(same.new_slot);
  EXPECT_EQ(same.record.candidates, std::vector<int>{0});
  EXPECT_DOUBLE_EQ(same.record.weights[0], 1.0);  // geometry weight + full ID support
  // Another ID there: no candidate, a new slot.
  EXPECT_TRUE(AssociateSlot(state, 0, SlotAt(6, 2, "456"), drifted_m, options).new_slot);
  // With a precise prediction the 3 m shift costs more than the null
  // hypothesis: a new slot too (merged later if it was the same).
  EXPECT_TRUE(AssociateSlot(state, 0, SlotAt(6, 2, "123"), kSigma_m, options).new_slot);
  // A partial reading that agrees supports it at the digit's confidence.
  const SlotLandmark& slot = state.slots[0];
  EXPECT_NEAR(IdSupport(slot, SlotAt(6, 2, "12?"), options), 1.0, 1e-12);
  EXPECT_EQ(IdSupport(slot, SlotAt(6, 2, "45?"), options), 0.0);
}

TEST(AssociationTest, WithoutMixtureAConfidentIdDecidesThenTheNearestNeighbour) {
  MapperOptions options;
  options.robust = RobustMode::kNone;
  MapState state = StateWithOneKeyframe();
  CreateSlot(&state, 0, SlotAt(3, 2, "7"), options);
  CreateSlot(&state, 0, SlotAt(5.6, 2), options);
  // Nearer to slot 1, but reading slot 0's ID.
  const SlotAssociation by_id = AssociateSlot(state, 0, SlotAt(5.0, 2, "7"), kSigma_m, options);
  ASSERT_FALSE(by_id.new_slot);
  EXPECT_EQ(by_id.record.chosen, 0);
  EXPECT_FALSE(by_id.record.has_null);
  const SlotAssociation by_distance = AssociateSlot(state, 0, SlotAt(5.55, 2), kSigma_m, options);
  ASSERT_FALSE(by_distance.new_slot);
  EXPECT_EQ(by_distance.record.chosen, 1);
}

}  // namespace
}  // namespace parkslam::mapping
