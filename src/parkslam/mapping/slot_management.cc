#include "parkslam/mapping/slot_management.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include "parkslam/common/angles.h"
#include "parkslam/common/convex_polygon.h"
#include "parkslam/mapping/association.h"
#include "parkslam/mapping/slot_id.h"

namespace parkslam::mapping {
namespace {

// What a removal leaves of a vote: below this it is gone.
constexpr double kVanishedVote = 1e-9;

// Keeps, of a record's candidates, those `keep` maps to a slot (-1: drop),
// each once, with the larger weight where two become one.
template <typename Map>
void RemapCandidates(SlotRecord* record, Map keep) {
  std::vector<int> candidates;
  std::vector<double> weights;
  for (size_t i = 0; i < record->candidates.size(); ++i) {
    const int s = keep(record->candidates[i]);
    if (s < 0) continue;
    const auto it = std::find(candidates.begin(), candidates.end(), s);
    if (it == candidates.end()) {
      candidates.push_back(s);
      weights.push_back(record->weights[i]);
    } else {
      double& w = weights[it - candidates.begin()];
      w = std::max(w, record->weights[i]);
    }
  }
  record->candidates = std::move(candidates);
  record->weights = std::move(weights);
}

}  // namespace

std::string TemporaryId(int temporary_number) {
  std::string id = "t";
  id += std::to_string(temporary_number);
  return id;
}

int CreateSlot(MapState* state, int keyframe, const SlotObservation& obs,
               const MapperOptions& options) {
  const SE2 pose = state->PoseOf(keyframe);
  SlotLandmark slot;
  for (int j = 0; j < kSlotCorners; ++j) {
    const Eigen::Vector2d p = pose * obs.corners_vehicle[j];
    slot.corners[j] = {p.x(), p.y()};
  }
  const Eigen::Vector2d entrance = obs.corners_vehicle[1] - obs.corners_vehicle[0];
  const Eigen::Vector2d side = obs.corners_vehicle[3] - obs.corners_vehicle[0];
  slot.angle_rad = SlotAngle(obs);
  if (std::abs(slot.angle_rad - kPi / 2) < options.right_angle_tolerance_rad) {
    slot.angle_rad = kPi / 2;
  }
  slot.width_m = entrance.norm();
  slot.depth_m = side.norm();
  slot.temporary_number = state->next_temporary_number++;
  state->slots.push_back(slot);
  const int index = static_cast<int>(state->slots.size()) - 1;

  SlotRecord record;
  record.keyframe = keyframe;
  record.observation = obs;
  record.candidates = {index};
  record.weights = {1.0};
  record.chosen = index;
  AddSlotRecord(state, std::move(record), options);
  return index;
}

void AddSlotRecord(MapState* state, SlotRecord record, const MapperOptions& options) {
  MoveEvidence(state, record, record.chosen, +1, options);
  if (state->slot_record_index.size() < state->slots.size()) {
    state->slot_record_index.resize(state->slots.size());
  }
  for (int c : record.candidates) {
    state->slot_record_index[static_cast<size_t>(c)].push_back(state->slot_records.size());
  }
  const int chosen = record.chosen;
  state->slot_records.push_back(std::move(record));
  UpdateIdOwner(state, chosen);
}

void MoveEvidence(MapState* state, const SlotRecord& record, int slot_index, int sign,
                  const MapperOptions& options) {
  if (slot_index < 0) return;
  SlotLandmark& slot = state->slots[slot_index];
  AddEvidence(record, sign, options, &slot.votes, &slot.observations, &slot.corner_observations);
}

void AddEvidence(const SlotRecord& record, int sign, const MapperOptions& options,
                 std::map<std::string, double>* votes, int* observations,
                 std::array<int, kSlotCorners>* corner_observations) {
  *observations += sign;
  for (int j = 0; j < kSlotCorners; ++j) {
    (*corner_observations)[j] += sign * static_cast<int>(record.observation.corner_observed[j]);
  }
  for (const IdHypothesis& h : FullIdHypotheses(record.observation.id, options.id_hypothesis_min)) {
    double& v = (*votes)[h.id];
    v += sign * h.probability;
    if (v < kVanishedVote) votes->erase(h.id);
  }
}

void UpdateIdOwner(MapState* state, int s) {
  for (const auto& [id, votes] : state->slots[s].votes) {
    auto it = state->id_owner.find(id);
    if (it == state->id_owner.end() || !state->slots[it->second.first].alive ||
        votes > it->second.second || it->second.first == s) {
      state->id_owner[id] = {s, votes};
    }
  }
}

void RebuildIdOwners(MapState* state) {
  state->id_owner.clear();
  for (int s = 0; s < static_cast<int>(state->slots.size()); ++s) {
    if (state->slots[s].alive) UpdateIdOwner(state, s);
  }
}

void RecomputeSlotEvidence(MapState* state, const MapperOptions& options) {
  for (SlotLandmark& slot : state->slots) {
    slot.votes = slot.retired_votes;
    slot.observations = slot.retired_observations;
    slot.corner_observations = slot.retired_corner_observations;
  }
  for (const SlotRecord& record : state->slot_records) {
    MoveEvidence(state, record, record.chosen, +1, options);
  }
  RebuildIdOwners(state);
}

int MergeDuplicates(MapState* state, const MapperOptions& options) {
  std::deque<SlotLandmark>& slots = state->slots;
  const int n = static_cast<int>(slots.size());
  std::vector<int> target(n);
  for (int s = 0; s < n; ++s) target[s] = s;
  int merged = 0;
  for (int a = 0; a < n; ++a) {
    if (!slots[a].alive) continue;
    for (int b = a + 1; b < n; ++b) {
      if (!slots[b].alive) continue;
      if ((slots[a].Corner(0) - slots[b].Corner(0)).norm() > options.merge_distance_m ||
          (slots[a].Corner(1) - slots[b].Corner(1)).norm() > options.merge_distance_m) {
        continue;
      }
      // Keep the better-observed slot.
      const bool keep_a = slots[a].observations >= slots[b].observations;
      const int keep = keep_a ? a : b, drop = keep_a ? b : a;
      slots[drop].alive = false;
      target[drop] = keep;
      // The dropped slot's retired evidence stays with the records' new slot.
      SlotLandmark& kept = slots[keep];
      const SlotLandmark& dropped = slots[drop];
      for (const auto& [id, votes] : dropped.retired_votes) kept.retired_votes[id] += votes;
      kept.retired_observations += dropped.retired_observations;
      for (int j = 0; j < kSlotCorners; ++j) {
        kept.retired_corner_observations[j] += dropped.retired_corner_observations[j];
      }
      ++merged;
      if (drop == a) break;
    }
  }
  auto resolve = [&target](int s) {
    while (target[s] != s) s = target[s];
    return s;
  };
  for (SlotRecord& record : state->slot_records) {
    RemapCandidates(&record, resolve);
    if (record.chosen >= 0) record.chosen = resolve(record.chosen);
  }
  return merged;
}

int PruneUnconfirmedSlots(MapState* state, const MapperOptions& options) {
  const int after = options.prune_unconfirmed_after_keyframes;
  if (after <= 0) return 0;
  std::deque<SlotLandmark>& slots = state->slots;
  // The last keyframe that saw each slot (records come in keyframe order).
  std::vector<int> last_seen(slots.size(), -1);
  for (const SlotRecord& record : state->slot_records) {
    for (int c : record.candidates) last_seen[static_cast<size_t>(c)] = record.keyframe;
  }
  const int before = static_cast<int>(state->keyframes.size()) - after;
  std::vector<bool> prune(slots.size(), false);
  int pruned = 0;
  for (size_t s = 0; s < slots.size(); ++s) {
    const SlotLandmark& slot = slots[s];
    if (slot.alive && slot.observations < options.min_observations && last_seen[s] < before) {
      prune[s] = true;
      ++pruned;
    }
  }
  if (pruned == 0) return 0;
  size_t kept = 0;
  for (SlotRecord& record : state->slot_records) {
    RemapCandidates(&record, [&prune](int s) { return prune[static_cast<size_t>(s)] ? -1 : s; });
    if (record.candidates.empty()) continue;  // it only ever named pruned slots
    if (record.chosen >= 0 && prune[static_cast<size_t>(record.chosen)])
      record.chosen = record.candidates.front();
    SlotRecord& into = state->slot_records[kept++];
    if (&into != &record) into = std::move(record);
  }
  state->slot_records.resize(kept);  // in place: storage reused, not reallocated
  for (size_t s = 0; s < slots.size(); ++s) {
    if (prune[s]) slots[s].alive = false;
  }
  return pruned;
}

int DropOverlappingSlots(MapState* state, const MapperOptions& options) {
  std::deque<SlotLandmark>& slots = state->slots;
  std::vector<int> order;
  for (int s = 0; s < static_cast<int>(slots.size()); ++s) {
    if (InTheMap(slots[s], options)) order.push_back(s);
  }
  // Named slots first (an ID read again and again is evidence of its own),
  // then the more observed.
  std::stable_sort(order.begin(), order.end(), [&slots](int a, int b) {
    const bool named_a = !slots[a].id.empty(), named_b = !slots[b].id.empty();
    if (named_a != named_b) return named_a;
    return slots[a].observations > slots[b].observations;
  });
  struct Kept {
    Eigen::Vector2d entrance;
    std::vector<Eigen::Vector2d> outline;
    double area_m2;
  };
  std::vector<Kept> kept;
  int dropped = 0;
  for (int s : order) {
    std::vector<Eigen::Vector2d> outline;
    for (int j = 0; j < kSlotCorners; ++j) outline.push_back(slots[s].Corner(j));
    const double area_m2 = PolygonArea(outline);
    // Named slots stay whatever they overlap; only unnamed ones are tested.
    const bool overlaps =
        slots[s].id.empty() && std::any_of(kept.begin(), kept.end(), [&](const Kept& k) {
          // Far apart: no need to clip (two slots are at most ~10 m across).
          if ((slots[s].Corner(0) - k.entrance).norm() > 20.0) return false;
          return ConvexOverlapArea(outline, k.outline) >
                 options.max_overlap_share * std::min(area_m2, k.area_m2);
        });
    if (overlaps) {
      slots[s].alive = false;
      ++dropped;
    } else {
      kept.push_back({slots[s].Corner(0), std::move(outline), area_m2});
    }
  }
  for (SlotRecord& record : state->slot_records) {
    if (record.chosen >= 0 && !slots[static_cast<size_t>(record.chosen)].alive) record.chosen = -1;
  }
  return dropped;
}

std::vector<std::string> IdsByVotes(const std::deque<SlotLandmark>& slots,
                                    const MapperOptions& options) {
  struct Claim {
    double votes;
    int slot;
    std::string id;
  };
  std::vector<Claim> claims;
  for (int s = 0; s < static_cast<int>(slots.size()); ++s) {
    const SlotLandmark& slot = slots[s];
    if (!slot.alive) continue;
    double total = 0.0;
    for (const auto& [id, votes] : slot.votes) total += votes;
    for (const auto& [id, votes] : slot.votes) {
      // A name needs enough agreeing readings and most of the slot's votes.
      if (votes >= options.id_min_votes && votes > 0.5 * total) claims.push_back({votes, s, id});
    }
  }
  std::sort(claims.begin(), claims.end(), [](const Claim& a, const Claim& b) {
    return a.votes > b.votes || (a.votes == b.votes && a.slot < b.slot);
  });
  std::vector<std::string> ids(slots.size());
  std::set<std::string> taken;
  for (const Claim& claim : claims) {
    std::string& id = ids[static_cast<size_t>(claim.slot)];
    if (!id.empty() || taken.count(claim.id) > 0) continue;
    id = claim.id;
    taken.insert(claim.id);
  }
  return ids;
}

void AssignIds(MapState* state, const MapperOptions& options) {
  const std::vector<std::string> ids = IdsByVotes(state->slots, options);
  for (size_t s = 0; s < state->slots.size(); ++s) state->slots[s].id = ids[s];
}

}  // namespace parkslam::mapping
