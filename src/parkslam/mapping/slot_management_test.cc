#include "parkslam/mapping/slot_management.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "parkslam/mapping/mapping_parts_test_util.h"

namespace parkslam::mapping {
namespace {

using test_util::SlotAt;
using test_util::StateWithOneKeyframe;

// A record of `obs` at keyframe 0 choosing `slot` alone.
SlotRecord RecordOf(const SlotObservation& obs, int slot) {
  SlotRecord record;
  record.observation = obs;
  record.candidates = {slot};
  record.weights = {1.0};
  record.chosen = slot;
  return record;
}

TEST(SlotManagementTest, NewSlotsTakeTemporaryNumbersAndTheirFirstEvidence) {
  MapperOptions options;
  MapState state = StateWithOneKeyframe();
  SlotObservation skewed = SlotAt(0, 0, "12");
  skewed.corners_vehicle[3] = {0.3, 5.3};  // 3 degrees off a right angle
  EXPECT_EQ(CreateSlot(&state, 0, skewed, options), 0);
  EXPECT_EQ(CreateSlot(&state, 0, SlotAt(10, 0), options), 1);
  const SlotLandmark& first = state.slots[0];
  EXPECT_EQ(first.temporary_number, 1);
  EXPECT_EQ(state.slots[1].temporary_number, 2);
  EXPECT_EQ(first.angle_rad, M_PI / 2);  // snapped
  EXPECT_NEAR(first.width_m, 2.5, 1e-12);
  EXPECT_EQ(first.observations, 1);
  EXPECT_EQ(first.corner_observations, (std::array<int, kSlotCorners>{1, 1, 0, 0}));
  EXPECT_DOUBLE_EQ(first.votes.at("12"), 1.0);
  EXPECT_EQ(state.id_owner.at("12").first, 0);
  EXPECT_EQ(state.slot_records.size(), 2u);
  EXPECT_EQ(state.slot_record_index[1], std::vector<size_t>{1});
  EXPECT_EQ(TemporaryId(12), "t12");
}

TEST(SlotManagementTest, EvidenceMovesWithTheChoiceAndVanishedVotesGo) {
  MapperOptions options;
  MapState state = StateWithOneKeyframe();
  CreateSlot(&state, 0, SlotAt(0, 0), options);
  CreateSlot(&state, 0, SlotAt(10, 0), options);
  const SlotRecord record = RecordOf(SlotAt(0, 0, "5"), 0);
  AddSlotRecord(&state, record, options);
  EXPECT_EQ(state.slots[0].observations, 2);
  EXPECT_EQ(state.id_owner.at("5").first, 0);
  MoveEvidence(&state, record, 0, -1, options);
  MoveEvidence(&state, record, 1, +1, options);
  EXPECT_EQ(state.slots[0].votes.count("5"), 0u);
  EXPECT_EQ(state.slots[0].observations, 1);
  EXPECT_EQ(state.slots[1].observations, 2);
  RebuildIdOwners(&state);
  EXPECT_EQ(state.id_owner.at("5").first, 1);
  // Recounting from the records gives the record's evidence back to the
  // slot it chose.
  RecomputeSlotEvidence(&state, options);
  EXPECT_EQ(state.slots[0].observations, 2);
  EXPECT_EQ(state.slots[1].observations, 1);
  EXPECT_EQ(state.id_owner.at("5").first, 0);
}

TEST(SlotManagementTest, DuplicatesMergeIntoTheBetterObservedSlot) {
  MapperOptions options;
  MapState state = StateWithOneKeyframe();
  CreateSlot(&state, 0, SlotAt(0, 0), options);
  CreateSlot(&state, 0, SlotAt(0.3, 0.2), options);  // within merge_distance_m
  CreateSlot(&state, 0, SlotAt(2.5, 0), options);    // the neighbour: stays
  AddSlotRecord(&state, RecordOf(SlotAt(0.3, 0.2), 1), options);
  SlotRecord both = RecordOf(SlotAt(0.1, 0.1), 1);
  both.candidates = {0, 1};
  both.weights = {0.2, 0.6};
  AddSlotRecord(&state, both, options);
  EXPECT_EQ(MergeDuplicates(&state, options), 1);
  EXPECT_FALSE(state.slots[0].alive);
  EXPECT_TRUE(state.slots[1].alive);
  EXPECT_TRUE(state.slots[2].alive);
  const SlotRecord& merged = state.slot_records.back();
  EXPECT_EQ(merged.candidates, std::vector<int>{1});
  EXPECT_EQ(merged.weights, std::vector<double>{0.6});
  EXPECT_EQ(merged.chosen, 1);
  EXPECT_EQ(state.slot_records[0].chosen, 1);  // the dropped slot's creating record
}

TEST(SlotManagementTest, UnconfirmedSlotsOfLongAgoArePruned) {
  MapperOptions options;
  options.prune_unconfirmed_after_keyframes = 10;
  MapState state = StateWithOneKeyframe();
  CreateSlot(&state, 0, SlotAt(0, 0), options);   // seen once: unconfirmed
  CreateSlot(&state, 0, SlotAt(10, 0), options);  // seen min_observations times
  for (int i = 1; i < options.min_observations; ++i) {
    AddSlotRecord(&state, RecordOf(SlotAt(10, 0), 1), options);
  }
  EXPECT_EQ(PruneUnconfirmedSlots(&state, options), 0);  // not long ago yet
  for (int k = 0; k < 10; ++k) state.keyframes.push_back(Keyframe{});
  EXPECT_EQ(PruneUnconfirmedSlots(&state, options), 1);
  EXPECT_FALSE(state.slots[0].alive);
  EXPECT_TRUE(state.slots[1].alive);
  EXPECT_EQ(state.slot_records.size(), static_cast<size_t>(options.min_observations));
}

TEST(SlotManagementTest, OfTwoSlotsSharingFloorTheLessObservedGoes) {
  MapperOptions options;
  MapState state = StateWithOneKeyframe();
  // Slot 0 and its neighbour 1 in a row (touching), slot 2 made across
  // half of slot 0 and half of a slot never seen (a wrong pairing), slot 3
  // the same but seen too rarely to count.
  const std::vector<double> x_m = {0.0, 2.5, -1.25, 1.25};
  const std::vector<int> seen = {5, 4, 4, 1};
  for (size_t s = 0; s < x_m.size(); ++s) {
    CreateSlot(&state, 0, SlotAt(x_m[s], 0), options);
    for (int i = 1; i < seen[s]; ++i) {
      AddSlotRecord(&state, RecordOf(SlotAt(x_m[s], 0), static_cast<int>(s)), options);
    }
  }
  EXPECT_EQ(DropOverlappingSlots(&state, options), 1);
  EXPECT_TRUE(state.slots[0].alive);
  EXPECT_TRUE(state.slots[1].alive);
  EXPECT_FALSE(state.slots[2].alive);  // half of slot 0's floor
  EXPECT_TRUE(state.slots[3].alive);   // below min_observations: left to the map's filter
  for (const SlotRecord& record : state.slot_records) EXPECT_NE(record.chosen, 2);
  // A little overlap is no reason: moved to overlap slot 0 by 0.2 m (a
  // share of 0.08), slot 2 stays at a limit of 0.1 and goes at 0.05.
  state.slots[2].alive = true;
  options.max_overlap_share = 0.1;
  for (int j = 0; j < kSlotCorners; ++j) state.slots[2].corners[j][0] -= 1.25 - 0.2;
  EXPECT_EQ(DropOverlappingSlots(&state, options), 0);
  options.max_overlap_share = 0.05;
  EXPECT_EQ(DropOverlappingSlots(&state, options), 1);
  // A slot with an ID stays, and goes first: the unnamed, better-observed
  // slot 0 under it is the one dropped.
  state.slots[2].alive = true;
  state.slots[2].id = "7";
  EXPECT_EQ(DropOverlappingSlots(&state, options), 1);
  EXPECT_TRUE(state.slots[2].alive);
  EXPECT_FALSE(state.slots[0].alive);
}

TEST(SlotManagementTest, AnIdGoesToTheSlotWithMostVotesForIt) {
  MapperOptions options;
  MapState state = StateWithOneKeyframe();
  CreateSlot(&state, 0, SlotAt(0, 0, "8"), options);
  CreateSlot(&state, 0, SlotAt(10, 0, "8"), options);
  CreateSlot(&state, 0, SlotAt(20, 0, "9"), options);
  for (int i = 0; i < 2; ++i) AddSlotRecord(&state, RecordOf(SlotAt(10, 0, "8"), 1), options);
  AddSlotRecord(&state, RecordOf(SlotAt(0, 0, "8"), 0), options);
  AssignIds(&state, options);
  EXPECT_EQ(state.slots[1].id, "8");  // 3 votes against 2
  EXPECT_EQ(state.slots[0].id, "");   // temporary
  EXPECT_EQ(state.slots[2].id, "");   // one vote: below id_min_votes
}

}  // namespace
}  // namespace parkslam::mapping
