#include "parkslam/mapping/back_line.h"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace parkslam::mapping {
namespace {

constexpr int kFarRight = 2;  // the far end of the side from corner 1
constexpr int kFarLeft = 3;   // the far end of the side from corner 0

// Rotation from the slot's entrance frame (x along corner 0 -> 1) to the map.
Eigen::Matrix2d EntranceRotation(const MapSlot& slot) {
  const Eigen::Vector2d e = (slot.corners_map[1] - slot.corners_map[0]).normalized();
  Eigen::Matrix2d R;
  R << e.x(), -e.y(), e.y(), e.x();
  return R;
}

// How far `right` is from continuing the row of `left` (its corner 0 on
// left's corner 1, the same entrance direction); infinity when it does not.
double NeighbourDistance(const MapSlot& left, const MapSlot& right, const BackLineOptions& o) {
  if (left.kind == SlotKind::kParallel || right.kind == SlotKind::kParallel) {
    return std::numeric_limits<double>::infinity();
  }
  const double d = (left.corners_map[1] - right.corners_map[0]).norm();
  const Eigen::Vector2d a = (left.corners_map[1] - left.corners_map[0]).normalized();
  const Eigen::Vector2d b = (right.corners_map[1] - right.corners_map[0]).normalized();
  const double angle = std::acos(std::clamp(a.dot(b), -1.0, 1.0));
  if (d > o.neighbour_corner_m || angle > o.neighbour_angle_rad) {
    return std::numeric_limits<double>::infinity();
  }
  return d;
}

}  // namespace

BackLineStats ShareBackLines(const BackLineOptions& options, std::vector<MapSlot>* slots) {
  std::vector<MapSlot>& s = *slots;
  const int n = static_cast<int>(s.size());
  BackLineStats stats;

  // The row: each slot's nearest right-hand neighbour, taken once.
  std::vector<int> right(n, -1), left(n, -1);
  for (int i = 0; i < n; ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (int j = 0; j < n; ++j) {
      if (j == i || left[j] >= 0) continue;
      const double d = NeighbourDistance(s[i], s[j], options);
      if (d < best) {
        best = d;
        right[i] = j;
      }
    }
    if (right[i] >= 0) left[right[i]] = i;
  }

  // Step 1: a far corner seen by the neighbour across the shared line. The
  // sources are the corners seen before this step, so nothing is copied
  // twice along a row.
  std::vector<std::array<bool, kSlotCorners>> seen(n);
  for (int i = 0; i < n; ++i) seen[i] = s[i].corner_observed;
  for (int i = 0; i < n; ++i) {
    MapSlot& slot = s[i];
    auto take = [&](int corner, int neighbour, int their_corner) {
      if (slot.corner_observed[corner] || neighbour < 0) return;
      const MapSlot& other = s[neighbour];
      if (!seen[neighbour][their_corner]) return;
      slot.corners_map[corner] = other.corners_map[their_corner];
      slot.corner_sigma_m[corner] = other.corner_sigma_m[their_corner];
      slot.corner_observed[corner] = true;
      ++stats.shared_corners;
    };
    take(kFarRight, right[i], kFarLeft);
    take(kFarLeft, left[i], kFarRight);
  }

  // Step 2: the slot's own depth and side direction from the far corner it
  // saw; kept, in the entrance frame, for step 3.
  std::vector<bool> has_side(n, false);
  std::vector<Eigen::Vector2d> side_local(n, Eigen::Vector2d::Zero());
  for (int i = 0; i < n; ++i) {
    MapSlot& slot = s[i];
    const bool far_left = slot.corner_observed[kFarLeft];
    const bool far_right = slot.corner_observed[kFarRight];
    if (!far_left && !far_right) continue;
    const Eigen::Vector2d left_side = slot.corners_map[kFarLeft] - slot.corners_map[0];
    const Eigen::Vector2d right_side = slot.corners_map[kFarRight] - slot.corners_map[1];
    Eigen::Vector2d side = far_left && far_right ? Eigen::Vector2d((left_side + right_side) / 2)
                                                 : (far_left ? left_side : right_side);
    if (far_left != far_right) {
      const int seen_corner = far_left ? kFarLeft : kFarRight;
      const int other = far_left ? kFarRight : kFarLeft;
      const int other_entrance = far_left ? 1 : 0;
      slot.corners_map[other] = slot.corners_map[other_entrance] + side;
      slot.corner_sigma_m[other] =
          std::hypot(slot.corner_sigma_m[seen_corner], options.within_slot_sigma_m);
      ++stats.from_own_side;
    }
    has_side[i] = true;
    side_local[i] = EntranceRotation(slot).transpose() * side;
  }

  // Steps 3 and 4: slots that saw no far corner.
  for (int i = 0; i < n; ++i) {
    MapSlot& slot = s[i];
    if (has_side[i]) continue;
    // The nearest slot of the row that saw its back line, walking both ways
    // (a row is a chain; the step count bounds a cycle).
    int source = -1;
    int l = left[i], r = right[i];
    for (int step = 0; step < n && source < 0 && (l >= 0 || r >= 0); ++step) {
      if (l >= 0 && has_side[l])
        source = l;
      else if (r >= 0 && has_side[r])
        source = r;
      if (l >= 0) l = left[l];
      if (r >= 0) r = right[r];
    }
    if (source >= 0) {
      const Eigen::Vector2d side = EntranceRotation(slot) * side_local[source];
      slot.corners_map[kFarLeft] = slot.corners_map[0] + side;
      slot.corners_map[kFarRight] = slot.corners_map[1] + side;
      slot.corner_sigma_m[kFarLeft] = slot.corner_sigma_m[kFarRight] = options.row_depth_sigma_m;
      ++stats.from_row;
    } else {
      slot.corner_sigma_m[kFarLeft] = slot.corner_sigma_m[kFarRight] = options.depth_prior_sigma_m;
      ++stats.guessed;
    }
  }
  return stats;
}

}  // namespace parkslam::mapping
