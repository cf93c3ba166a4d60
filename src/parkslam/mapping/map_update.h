#ifndef PARKSLAM_MAPPING_MAP_UPDATE_H_
#define PARKSLAM_MAPPING_MAP_UPDATE_H_

// A map that outlives one drive (docs/mapping.md, "Updating a map"): the
// map of an earlier drive, updated from the map of a new drive of the same
// lot. Garages change between drives: slots are repainted or moved, tags
// moved or taken down, rows added. The update keeps what still holds,
// replaces what changed, adds what is new and stamps every landmark the new
// drive confirmed with its label (MapSlot::last_confirmed).
//
// 1. Alignment. The new map lives in the frame of its own drive. It is laid
//    on the old one by the landmarks both name alike (slots by painted ID,
//    tags by number): each such pair proposes the transform (a slot by its
//    entrance corners, a tag by its place and normal), the proposal that
//    most pairs agree with within alignment_inlier_m wins, and a least-
//    squares fit on the points of the agreeing pairs refines it. Changed
//    landmarks disagree and are left out.
// 2. Slots, new onto old. A new slot with the painted ID of an old one is
//    that slot: where its seen entrance corners lie within same_place_m of
//    the old ones it is confirmed (the old geometry kept, but for corners
//    the old map only guessed and the new drive saw); where both moved
//    alike, it moved (the new geometry replaces the old); where they
//    disagree (one corner put on a neighbour's line, as a detector does
//    beside a slot painted anew), the old slot is kept as it was. A new slot with no such ID that
//    covers an old slot (entrance midpoints within same_slot_m, alike in direction) is that slot
//    repainted: a new painted ID replaces the old one; an unread one keeps it; the geometry as
//    above. Any other new slot is added (a temporary ID renumbered past the old ones).
// 3. Tags: the same number within same_place_m confirmed, farther moved.
//    An old tag the new drive does not have is removed when that drive had
//    it in the front camera's view (from camera_forward_m ahead of the
//    car: within tag_view_range_m, inside tag_view_half_angle_rad of the
//    heading, facing the camera within 60 degrees, no obstacle of the map
//    between) at tag_view_min_keyframes keyframes or more: it is gone.
//    Otherwise it is kept, unconfirmed.
// Old slots the new drive did not see stay as they were: a slot missed is
// not a slot gone (parked cars hide them).

#include <string>

#include "parkslam/common/se2.h"
#include "parkslam/common/trajectory.h"
#include "parkslam/map/semantic_map.h"

namespace parkslam::mapping {

struct MapUpdateOptions {
  // Stamped on every landmark the drive confirmed ("2026-12-02", a drive's
  // name).
  std::string label;
  double alignment_inlier_m = 0.3;
  int alignment_min_pairs = 3;
  // ... and at least this share of the pairs: lots that number their slots
  // alike, row by row, agree on a few by chance.
  double alignment_min_share = 0.5;
  double same_place_m = 0.25;
  double same_slot_m = 1.0;
  double same_slot_angle_rad = 0.35;
  // The front camera, this far ahead of the vehicle frame's origin (the
  // rear axle): where the view is judged from.
  double camera_forward_m = 1.8;
  double tag_view_range_m = 18.0;
  double tag_view_half_angle_rad = 0.7;
  int tag_view_min_keyframes = 10;

  bool IsValid(std::string* error) const;
};

struct MapUpdateReport {
  SE2 T_old_new;  // the new drive's frame in the old map's
  int alignment_pairs = 0, alignment_inliers = 0;
  int slots_confirmed = 0;
  int slots_moved = 0;
  int slots_repainted = 0;  // a new painted ID, or a first one for a temporary ID
  int slots_added = 0;
  int slots_disputed = 0;     // seen, but the sighting disagreed with itself: kept
  int slots_unconfirmed = 0;  // old slots the drive did not see
  int tags_confirmed = 0, tags_moved = 0, tags_added = 0, tags_removed = 0;
  int tags_unconfirmed = 0;
};

// Updates `old_map` from `new_map`, the map of a new drive whose keyframes
// (in new_map's frame) are `new_drive`. Throws std::invalid_argument for
// invalid options, and std::runtime_error when fewer than
// alignment_min_pairs landmarks, or less than alignment_min_share of those
// named alike, agree on an alignment (the drive is not of this lot, or saw
// too little of it).
SemanticMap UpdateMap(const SemanticMap& old_map, const SemanticMap& new_map,
                      const Trajectory& new_drive, const MapUpdateOptions& options,
                      MapUpdateReport* report = nullptr);

}  // namespace parkslam::mapping

#endif  // PARKSLAM_MAPPING_MAP_UPDATE_H_
