#include "parkslam/mapping/map_update.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>

namespace parkslam::mapping {
namespace {

// A row of 10 slots along y = 0 (entrance on y = 0, backs at y = -5.3)
// with IDs 1-10, and three tags on a wall at y = 6 facing south.
SemanticMap Lot() {
  SemanticMap map;
  for (int i = 0; i < 10; ++i) {
    MapSlot s;
    s.id = std::to_string(i + 1);
    const double x = 2.5 * i;
    s.corners_map = {Eigen::Vector2d(x + 2.5, 0), Eigen::Vector2d(x, 0), Eigen::Vector2d(x, -5.3),
                     Eigen::Vector2d(x + 2.5, -5.3)};
    s.corner_observed = {true, true, false, false};
    s.corner_sigma_m = {0.02, 0.02, 0.4, 0.4};
    s.observation_count = 5;
    map.slots.push_back(s);
  }
  map.obstacles.push_back({ObstacleKind::kWall, {Eigen::Vector2d(-5, 6), Eigen::Vector2d(30, 6)}});
  for (int k = 0; k < 3; ++k) {
    MapTag t;
    t.tag_id = 20 + k;
    t.p_map = Eigen::Vector2d(4.0 + 8.0 * k, 6.0);
    t.yaw_map_rad = -M_PI / 2;
    t.obstacle_index = 0;
    map.tags.push_back(t);
  }
  return map;
}

SemanticMap InFrame(const SE2& T_new_old, SemanticMap map) {
  for (MapSlot& s : map.slots) {
    for (Eigen::Vector2d& c : s.corners_map) c = T_new_old * c;
  }
  for (MapTag& t : map.tags) {
    t.p_map = T_new_old * t.p_map;
    t.yaw_map_rad += T_new_old.yaw();
  }
  map.obstacles.clear();
  return map;
}

// Along the aisle (y = 3) eastwards, facing the tags' wall: keyframes
// every 0.25 m from x = 0 to 25, heading north-north-east.
Trajectory Drive() {
  Trajectory drive;
  for (int i = 0; i <= 100; ++i) {
    drive.push_back({TimeNs{i} * 100'000'000, SE2(0.25 * i, 3.0, M_PI / 2 - 0.3)});
  }
  return drive;
}

TEST(MapUpdateTest, KeepsWhatHoldsReplacesWhatChangedAndRemovesAGoneTag) {
  const SemanticMap old_map = Lot();
  // The lot as it is now, in the new drive's own frame.
  SemanticMap now = old_map;
  for (Eigen::Vector2d& c : now.slots[3].corners_map) c.y() += 0.5;  // slot 4 moved
  now.slots[6].id = "77";                                            // slot 7 repainted
  now.slots[8].corner_observed = {true, true, true, true};           // slot 9's back seen
  now.slots[8].corners_map[2].y() = -5.0;
  now.slots[8].corners_map[3].y() = -5.0;
  now.tags[1].p_map.x() += 4.0;          // tag 21 moved along the wall
  now.tags.erase(now.tags.begin() + 2);  // tag 22 taken down
  MapSlot added = now.slots[9];          // a new slot past the row
  for (Eigen::Vector2d& c : added.corners_map) c.x() += 3.0;
  added.id = "t1";
  added.temporary = true;
  now.slots.push_back(added);
  now.slots.erase(now.slots.begin());  // slot 1 not seen this time
  const SE2 T_new_old(3.0, -2.0, 0.4);
  const SemanticMap new_map = InFrame(T_new_old, now);
  const Trajectory drive = Transformed(T_new_old, Drive());

  MapUpdateOptions options;
  options.label = "drive 2";
  MapUpdateReport r;
  const SemanticMap out = UpdateMap(old_map, new_map, drive, options, &r);

  EXPECT_LT((r.T_old_new.translation() - T_new_old.inverse().translation()).norm(), 1e-9);
  EXPECT_NEAR(r.T_old_new.yaw(), -0.4, 1e-9);
  EXPECT_EQ(r.slots_moved, 1);
  EXPECT_EQ(r.slots_repainted, 1);
  EXPECT_EQ(r.slots_added, 1);
  EXPECT_EQ(r.slots_confirmed, 8);  // 2, 3, 5-10 (7 repainted in place)
  EXPECT_EQ(r.slots_unconfirmed, 1);
  EXPECT_EQ(r.tags_confirmed, 1);
  EXPECT_EQ(r.tags_moved, 1);
  EXPECT_EQ(r.tags_removed, 1);
  ASSERT_EQ(out.slots.size(), 11u);
  EXPECT_NEAR(out.slots[3].corners_map[0].y(), 0.5, 1e-9);  // at its new place
  EXPECT_EQ(out.slots[3].last_confirmed, "drive 2");
  EXPECT_EQ(out.slots[6].id, "77");
  EXPECT_NEAR(out.slots[6].corners_map[1].x(), 15.0, 1e-9);
  EXPECT_TRUE(out.slots[8].corner_observed[2]);  // the back seen now
  EXPECT_NEAR(out.slots[8].corners_map[2].y(), -5.0, 1e-9);
  EXPECT_NEAR(out.slots[8].corners_map[0].y(), 0.0, 1e-9);  // the rest kept
  EXPECT_EQ(out.slots[0].last_confirmed, "");               // slot 1: kept, unconfirmed
  EXPECT_EQ(out.slots[10].id, "t1");
  ASSERT_EQ(out.tags.size(), 2u);
  EXPECT_EQ(out.tags[0].tag_id, 20);
  EXPECT_EQ(out.tags[1].tag_id, 21);
  EXPECT_NEAR(out.tags[1].p_map.x(), 16.0, 1e-9);
  EXPECT_EQ(out.tags[1].obstacle_index, 0);  // still on its wall
}

// The old map's entrance stands (its frame is kept); a map without one
// takes the new drive's, moved into the old frame.
TEST(MapUpdateTest, KeepsTheOldEntranceOrTakesTheNewDrives) {
  const SE2 T_new_old(3.0, -2.0, 0.4);
  SemanticMap new_map = InFrame(T_new_old, Lot());
  new_map.entrance = T_new_old * SE2(-1.0, 3.0, 0.1);
  const Trajectory drive = Transformed(T_new_old, Drive());
  SemanticMap old_map = Lot();
  const SemanticMap taken = UpdateMap(old_map, new_map, drive, {}, nullptr);
  ASSERT_TRUE(taken.entrance.has_value());
  EXPECT_LT((taken.entrance->translation() - Eigen::Vector2d(-1.0, 3.0)).norm(), 1e-9);
  EXPECT_NEAR(taken.entrance->yaw(), 0.1, 1e-9);
  old_map.entrance = SE2(-2.0, 3.0, 0.0);
  const SemanticMap kept = UpdateMap(old_map, new_map, drive, {}, nullptr);
  ASSERT_TRUE(kept.entrance.has_value());
  EXPECT_NEAR(kept.entrance->x(), -2.0, 1e-12);
}

TEST(MapUpdateTest, ATagNeverInViewIsKept) {
  const SemanticMap old_map = Lot();
  SemanticMap now = old_map;
  now.tags.erase(now.tags.begin() + 2);
  // The drive keeps west of x = 8 and looks east along the row: tag 22 at
  // x = 20 is never within 8 m in front.
  Trajectory drive;
  for (int i = 0; i <= 10; ++i) drive.push_back({TimeNs{i} * 100'000'000, SE2(0.5 * i, 3.0, 0.0)});
  MapUpdateReport r;
  const SemanticMap out = UpdateMap(old_map, now, drive, {}, &r);
  EXPECT_EQ(r.tags_removed, 0);
  EXPECT_EQ(r.tags_unconfirmed, 1);
  EXPECT_EQ(out.tags.size(), 3u);
}

TEST(MapUpdateTest, AMisreadIdDoesNotMoveAnotherSlotOntoThisOne) {
  const SemanticMap old_map = Lot();
  SemanticMap now = old_map;
  now.slots[2].id = "8";  // slot 3 read as 8, which lies 12.5 m away
  now.slots.erase(now.slots.begin() + 7);
  MapUpdateReport r;
  const SemanticMap out = UpdateMap(old_map, now, Drive(), {}, &r);
  EXPECT_EQ(r.slots_moved, 0);
  EXPECT_EQ(out.slots[7].id, "8");
  EXPECT_NEAR(out.slots[7].corners_map[1].x(), 17.5, 1e-9);  // where it was
  EXPECT_EQ(out.slots[2].id, "3");  // the ID is another slot's: not renamed
}

TEST(MapUpdateTest, ASightingAtOddsWithItselfKeepsTheSlot) {
  const SemanticMap old_map = Lot();
  SemanticMap now = old_map;
  now.slots[4].corners_map[0].y() += 0.5;  // one entrance corner on a neighbour's line
  MapUpdateReport r;
  const SemanticMap out = UpdateMap(old_map, now, Drive(), {}, &r);
  EXPECT_EQ(r.slots_disputed, 1);
  EXPECT_EQ(r.slots_moved, 0);
  EXPECT_NEAR(out.slots[4].corners_map[0].y(), 0.0, 1e-9);
}

TEST(MapUpdateTest, RefusesADriveOfAnotherLot) {
  SemanticMap other = Lot();
  for (MapSlot& s : other.slots) s.id = "x" + s.id;
  for (MapTag& t : other.tags) t.tag_id += 100;
  EXPECT_THROW(UpdateMap(Lot(), other, Drive(), {}), std::runtime_error);
  MapUpdateOptions bad;
  bad.same_place_m = 2.0;
  EXPECT_THROW(UpdateMap(Lot(), Lot(), Drive(), bad), std::invalid_argument);
}

}  // namespace
}  // namespace parkslam::mapping
