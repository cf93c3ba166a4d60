#include "parkslam/mapping/map_graph.h"

#include <gtest/gtest.h>

#include <Eigen/LU>

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

// Eleven keyframes 1 m apart along x; slot A seen from the first three,
// slot B, its mirror image about x = 5, from the last three. Relative to
// the map as a whole (the gauge of ComputeCornerCovariances) the two are
// equally sure; with the first keyframe as the gauge, B would carry the
// whole chain's drift and A none of it.
TEST(MapGraphTest, CornerCovariancesAreRelativeToTheMapNotToTheStart) {
  MapperOptions options;
  MapState state = StateWithOneKeyframe();
  for (int k = 1; k <= 10; ++k) {
    Keyframe keyframe;
    keyframe.pose = {static_cast<double>(k), 0.0, 0.0};
    keyframe.T_previous_this = SE2(1.0, 0.0, 0.0);
    keyframe.covariance = Eigen::Vector3d(1e-4, 1e-4, 1e-5).asDiagonal();
    state.keyframes.push_back(keyframe);
  }
  const auto see = [&](int slot, int keyframe, double x_m) {
    SlotRecord record;
    record.keyframe = keyframe;
    record.observation = SlotAt(x_m - keyframe, 2);
    record.candidates = {slot};
    record.weights = {1.0};
    record.chosen = slot;
    AddSlotRecord(&state, record, options);
  };
  CreateSlot(&state, 0, SlotAt(0.0, 2), options);
  see(0, 1, 0.0);
  see(0, 2, 0.0);
  CreateSlot(&state, 10, SlotAt(-2.5, 2), options);
  see(1, 9, 7.5);
  see(1, 8, 7.5);
  CornerCovariances covariances;
  ASSERT_TRUE(ComputeCornerCovariances(&state, options, &covariances));
  ASSERT_EQ(covariances.size(), 2u);
  for (const auto& slot : covariances) {
    // The entrance corners were seen, the far ones not (their sigma comes
    // from the row: back_line.h).
    for (int j : {0, 1}) {
      ASSERT_TRUE(slot[j].has_value());
      EXPECT_GT(slot[j]->determinant(), 0.0);
      EXPECT_NEAR((*slot[j])(0, 1), (*slot[j])(1, 0), 1e-12);
    }
    EXPECT_FALSE(slot[2].has_value());
    EXPECT_FALSE(slot[3].has_value());
  }
  // A's entrance corner at (0, 2) mirrors B's at (10, 2).
  const double a = covariances[0][0]->trace(), b = covariances[1][1]->trace();
  EXPECT_NEAR(a / b, 1.0, 0.1);
  // Less than the chain's own drift between them (8 m at 1e-4 m^2 a metre,
  // and its yaw), which an anchor at the start would give B.
  EXPECT_LT(b, 2.0 * 8e-4);
  EXPECT_GT(b, 1e-5);
  // The graph is left as it was: covariances do not move the estimate.
  EXPECT_EQ(state.keyframes[0].pose, (std::array<double, 3>{0.0, 0.0, 0.0}));
}

}  // namespace
}  // namespace parkslam::mapping
