#include "parkslam/mapping/map_graph.h"

#include <gtest/gtest.h>

#include "parkslam/mapping/mapping_parts_test_util.h"
#include "parkslam/mapping/slot_management.h"

namespace parkslam::mapping {
namespace {

using test_util::SlotAt;
using test_util::StateWithOneKeyframe;

// Two keyframes 1 m apart along x, exact odometry.
MapState TwoKeyframes() {
  MapState state = StateWithOneKeyframe();
  Keyframe second;
  second.pose = {1.0, 0.0, 0.0};
  second.T_previous_this = SE2(1.0, 0.0, 0.0);
  second.covariance = Eigen::Matrix3d::Identity() * 1e-4;
  state.keyframes.push_back(second);
  return state;
}

TEST(MapGraphTest, AnEmptyStateSolvesNothing) {
  MapState state;
  const MapGraphSolve solve = SolveMapGraph(&state, 0, 10, true, MapperOptions{});
  EXPECT_EQ(solve.residual_blocks, 0);
  EXPECT_TRUE(solve.changed.empty());
}

TEST(MapGraphTest, TheSecondKeyframeAndTheSlotMeetTheirObservations) {
  MapperOptions options;
  MapState state = TwoKeyframes();
  // The slot as seen from keyframe 0; the second keyframe, really at x = 1,
  // is believed 0.2 m too far and sees it 1 m nearer.
  CreateSlot(&state, 0, SlotAt(3, 2), options);
  state.keyframes[1].pose = {1.2, 0.0, 0.0};
  SlotRecord record;
  record.keyframe = 1;
  record.observation = SlotAt(2, 2);
  record.candidates = {0};
  record.weights = {1.0};
  record.chosen = 0;
  AddSlotRecord(&state, record, options);
  const MapGraphSolve solve = SolveMapGraph(&state, 0, 50, true, options);
  // Odometry, two corner factors, one shape factor.
  EXPECT_EQ(solve.residual_blocks, 4);
  EXPECT_GT(solve.iterations, 0);
  EXPECT_EQ(state.keyframes[0].pose, (std::array<double, 3>{0.0, 0.0, 0.0}));  // the anchor
  EXPECT_NEAR(state.keyframes[1].pose[0], 1.0, 1e-3);
  EXPECT_NEAR(state.slots[0].corners[0][0], 3.0, 1e-3);
  EXPECT_NEAR(state.slots[0].corners[1][1], 2.0, 1e-3);
  EXPECT_TRUE(solve.changed.empty());
}

TEST(MapGraphTest, AMixtureThatPrefersAnotherSlotIsReportedNotApplied) {
  MapperOptions options;
  MapState state = TwoKeyframes();
  CreateSlot(&state, 0, SlotAt(3, 2), options);
  CreateSlot(&state, 0, SlotAt(5.5, 2), options);
  // Seen from keyframe 1 where slot 1 is, but associated with slot 0 first.
  SlotRecord record;
  record.keyframe = 1;
  record.observation = SlotAt(4.5, 2);
  record.candidates = {0, 1};
  record.weights = {0.5, 0.5};
  record.has_null = true;
  record.chosen = 0;
  AddSlotRecord(&state, record, options);
  const MapGraphSolve solve = SolveMapGraph(&state, 0, 50, true, options);
  ASSERT_EQ(solve.changed.size(), 1u);
  EXPECT_EQ(solve.changed[0].record, 2u);
  EXPECT_EQ(solve.changed[0].before, 0);
  EXPECT_EQ(solve.changed[0].after, 1);
  EXPECT_EQ(state.slot_records[2].chosen, 0);  // slot management applies it
}

TEST(MapGraphTest, AWindowedSolveHoldsTheKeyframesBeforeItFixed) {
  MapperOptions options;
  MapState state = TwoKeyframes();
  state.keyframes[1].pose = {1.2, 0.0, 0.0};
  const MapGraphSolve windowed = SolveMapGraph(&state, 1, 50, false, options);
  EXPECT_EQ(windowed.residual_blocks, 1);
  EXPECT_EQ(state.keyframes[0].pose, (std::array<double, 3>{0.0, 0.0, 0.0}));
  EXPECT_NEAR(state.keyframes[1].pose[0], 1.0, 1e-6);
}

}  // namespace
}  // namespace parkslam::mapping
