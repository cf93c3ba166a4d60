#include "parkslam/mapping/back_line.h"

#include <gtest/gtest.h>

#include <vector>

namespace parkslam::mapping {
namespace {

// A slot of a row along +x at y = 0 reaching north to y = depth_m, its far
// corners at guess_depth_m when not seen.
MapSlot RowSlot(double x_m, double width_m, double depth_m, bool far_seen, double guess_depth_m) {
  MapSlot s;
  const double d = far_seen ? depth_m : guess_depth_m;
  s.corners_map = {Eigen::Vector2d(x_m, 0), Eigen::Vector2d(x_m + width_m, 0),
                   Eigen::Vector2d(x_m + width_m, d), Eigen::Vector2d(x_m, d)};
  s.corner_observed = {true, true, far_seen, far_seen};
  s.corner_sigma_m = {0.02, 0.02, far_seen ? 0.03 : 0.4, far_seen ? 0.03 : 0.4};
  return s;
}

TEST(BackLineTest, NeighboursShareWhatOneOfThemSawOfTheBackLine) {
  // A row 6.1 m deep whose first slot alone saw its back line; the guess is
  // the standard 5.3 m.
  std::vector<MapSlot> slots;
  for (int k = 0; k < 4; ++k) slots.push_back(RowSlot(2.5 * k, 2.5, 6.1, k == 0, 5.3));
  // A slot of another row, 20 m away, alone with its guess.
  MapSlot alone = RowSlot(40.0, 2.5, 6.1, false, 5.3);
  slots.push_back(alone);
  BackLineOptions options;
  const BackLineStats stats = ShareBackLines(options, &slots);

  EXPECT_EQ(stats.shared_corners, 1);  // slot 1's far left corner is slot 0's far right
  EXPECT_EQ(stats.from_own_side, 1);   // slot 1's far right from its depth
  EXPECT_EQ(stats.from_row, 2);        // slots 2 and 3
  EXPECT_EQ(stats.guessed, 1);

  EXPECT_TRUE(slots[1].corner_observed[3]);
  EXPECT_DOUBLE_EQ(slots[1].corner_sigma_m[3], 0.03);
  EXPECT_FALSE(slots[1].corner_observed[2]);
  EXPECT_GT(slots[1].corner_sigma_m[2], 0.03);
  EXPECT_LT(slots[1].corner_sigma_m[2], 0.1);
  for (int k = 1; k < 4; ++k) {
    EXPECT_NEAR(slots[k].corners_map[2].y(), 6.1, 1e-9) << k;
    EXPECT_NEAR(slots[k].corners_map[3].y(), 6.1, 1e-9) << k;
    EXPECT_NEAR(slots[k].corners_map[3].x(), 2.5 * k, 1e-9) << k;
  }
  EXPECT_DOUBLE_EQ(slots[3].corner_sigma_m[2], options.row_depth_sigma_m);
  EXPECT_FALSE(slots[3].corner_observed[2]);
  // The lone slot keeps the guess and says how unsure it is.
  EXPECT_NEAR(slots[4].corners_map[2].y(), 5.3, 1e-9);
  EXPECT_DOUBLE_EQ(slots[4].corner_sigma_m[2], options.depth_prior_sigma_m);
  // Seen corners are left as they were.
  EXPECT_NEAR(slots[0].corners_map[2].y(), 6.1, 1e-9);
  EXPECT_DOUBLE_EQ(slots[0].corner_sigma_m[2], 0.03);
}

// Slots of the same row turned the other way, or a parallel slot, are no
// neighbours: nothing crosses between them.
TEST(BackLineTest, NoSharingAcrossRowsFacingAwayOrWithParallelSlots) {
  std::vector<MapSlot> slots = {RowSlot(0.0, 2.5, 6.1, true, 5.3)};
  MapSlot facing_away = RowSlot(2.5, 2.5, 6.1, false, 5.3);
  // Corner 0 on the first slot's corner 1, but the entrance runs west.
  std::swap(facing_away.corners_map[0], facing_away.corners_map[1]);
  facing_away.corners_map[0] = Eigen::Vector2d(2.5, 0.0);
  facing_away.corners_map[1] = Eigen::Vector2d(0.0, 0.0);
  facing_away.corners_map[2] = Eigen::Vector2d(0.0, -5.3);
  facing_away.corners_map[3] = Eigen::Vector2d(2.5, -5.3);
  slots.push_back(facing_away);
  MapSlot parallel = RowSlot(2.5, 6.0, 2.5, false, 2.5);
  parallel.kind = SlotKind::kParallel;
  slots.push_back(parallel);
  const BackLineStats stats = ShareBackLines(BackLineOptions(), &slots);
  EXPECT_EQ(stats.shared_corners, 0);
  EXPECT_EQ(stats.from_row, 0);
  EXPECT_EQ(stats.guessed, 2);
  EXPECT_NEAR(slots[1].corners_map[3].y(), -5.3, 1e-9);
}

}  // namespace
}  // namespace parkslam::mapping
