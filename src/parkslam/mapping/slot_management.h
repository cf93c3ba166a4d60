#ifndef PARKSLAM_MAPPING_SLOT_MANAGEMENT_H_
#define PARKSLAM_MAPPING_SLOT_MANAGEMENT_H_

// Slot management (paper III-C): slots added lazily under temporary IDs
// ("t12"), the evidence the records give each slot (observations, corners
// seen, votes for IDs), the current owner of each ID, duplicate merging,
// pruning of slots never confirmed, and the final naming of slots by their
// votes. Works on the map state; the graph (map_graph.h) only moves corners
// and records' choices.

#include <array>
#include <deque>
#include <map>
#include <string>
#include <vector>

#include "parkslam/mapping/map_state.h"
#include "parkslam/mapping/mapper_options.h"
#include "parkslam/sensor/sensor_data.h"

namespace parkslam::mapping {

// The name of a slot without an ID in the map: "t12" (paper III-C).
std::string TemporaryId(int temporary_number);

// A new slot from an observation made at `keyframe`, with its creating
// record (tied to it without a null component, so that no slot is ever
// left without a factor); its corner angle snapped to 90 degrees within
// right_angle_tolerance_rad. Returns its index.
int CreateSlot(MapState* state, int keyframe, const SlotObservation& observation,
               const MapperOptions& options);

// Appends an associated record: its evidence goes to the chosen slot, it is
// filed under each candidate, and the chosen slot's IDs may change owner.
void AddSlotRecord(MapState* state, SlotRecord record, const MapperOptions& options);

// Adds (sign +1) or removes (-1) what one record says of a slot
// (observation count, corners seen, ID votes); nothing for slot -1.
void MoveEvidence(MapState* state, const SlotRecord& record, int slot, int sign,
                  const MapperOptions& options);
// The same, to any tallies: a slot's own, or what its retired records said.
void AddEvidence(const SlotRecord& record, int sign, const MapperOptions& options,
                 std::map<std::string, double>* votes, int* observations,
                 std::array<int, kSlotCorners>* corner_observations);

// Each ID's owner: the alive slot with most votes for it.
void UpdateIdOwner(MapState* state, int slot);
void RebuildIdOwners(MapState* state);
// Recounts every slot's evidence from its retired tallies and the records'
// current choices, then the owners.
void RecomputeSlotEvidence(MapState* state, const MapperOptions& options);

// A slot the map shows: alive and seen at least min_observations times
// (fewer: spurious).
inline bool InTheMap(const SlotLandmark& slot, const MapperOptions& options) {
  return slot.alive && slot.observations >= options.min_observations;
}

// Merges alive slots whose entrance corners both lie within
// merge_distance_m, keeping the better-observed one; the records' candidates
// and choices move to it. Returns how many were merged.
int MergeDuplicates(MapState* state, const MapperOptions& options);

// Drops the slots with fewer than min_observations not seen in the last
// prune_unconfirmed_after_keyframes keyframes, and the records that name
// only them. Returns how many were pruned.
int PruneUnconfirmedSlots(MapState* state, const MapperOptions& options);

// Two slots cannot share floor. Walks the alive slots seen at least
// min_observations times, named ones first and then from the most observed
// down, and drops each slot without an ID that overlaps one kept before by
// more than max_overlap_share of the smaller one's area: a wrong pairing
// across real slots, which the merge by entrance corners cannot catch.
// Named slots stay (their ID is evidence of its own). The records that
// chose a dropped slot then choose none (null). Run at the end of mapping,
// after AssignIds; nothing is solved after it. Returns how many it dropped.
int DropOverlappingSlots(MapState* state, const MapperOptions& options);

// Names each alive slot by its votes: an ID needs id_min_votes and most of
// the slot's votes, and goes to the slot with most votes for it; the rest
// stay temporary.
void AssignIds(MapState* state, const MapperOptions& options);
// The same names, by slot index ("" for temporary), without setting them:
// what the slots would be called if the drive ended now.
std::vector<std::string> IdsByVotes(const std::deque<SlotLandmark>& slots,
                                    const MapperOptions& options);

}  // namespace parkslam::mapping

#endif  // PARKSLAM_MAPPING_SLOT_MANAGEMENT_H_
