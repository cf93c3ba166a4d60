#include "parkslam/mapping/association.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "parkslam/common/angles.h"
#include "parkslam/mapping/slot_id.h"

namespace parkslam::mapping {
namespace {

double Square(double x) { return x * x; }

// A plausible slot's corner angle is at least this far from 0 and pi
// (20 degrees), and its entrance and side at least this long.
constexpr double kMinSlotAngleRad = 0.35;
constexpr double kMinSlotSide_m = 0.5;

struct Candidate {
  int slot;
  double weight, chi2, cost, entrance_distance_m;
};

// The alive slots whose entrance lies within id_search_radius_m of the
// predicted one and that are neighbours (nn_search_radius_m) or whose IDs
// support the reading, by cost (-log weight + chi2 / 2), at most
// max_candidates.
std::vector<Candidate> Candidates(const MapState& state,
                                  const std::array<Eigen::Vector2d, kSlotCorners>& predicted,
                                  const SlotObservation& obs, double prediction_sigma_m,
                                  const MapperOptions& options) {
  std::vector<Candidate> candidates;
  for (int s = 0; s < static_cast<int>(state.slots.size()); ++s) {
    const SlotLandmark& slot = state.slots[s];
    if (!slot.alive) continue;
    const double d0 = (slot.Corner(0) - predicted[0]).norm();
    const double d1 = (slot.Corner(1) - predicted[1]).norm();
    const double entrance_m = std::max(d0, d1);
    if (entrance_m > options.id_search_radius_m) continue;
    const double support = IdSupport(slot, obs, options);
    const bool neighbour = entrance_m <= options.nn_search_radius_m;
    if (!neighbour && support < options.id_hypothesis_min) continue;
    Candidate c{s, std::min(1.0, options.geometry_weight + support), 0.0, 0.0, entrance_m};
    for (int j = 0; j < kSlotCorners; ++j) {
      c.chi2 += (slot.Corner(j) - predicted[j]).squaredNorm() /
                (Square(CornerSigma(obs, j, options)) + Square(prediction_sigma_m));
    }
    c.cost = -std::log(c.weight) + 0.5 * c.chi2;
    candidates.push_back(c);
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& a, const Candidate& b) { return a.cost < b.cost; });
  if (static_cast<int>(candidates.size()) > options.max_candidates) {
    candidates.resize(options.max_candidates);
  }
  return candidates;
}

// The plain front-end of the paper's baseline: a confident ID decides;
// otherwise the nearest neighbour within the gate; -1: a new slot.
int ChooseWithoutMixture(const MapState& state, const std::vector<Candidate>& candidates,
                         const Eigen::Vector2d& predicted_corner0, const SlotObservation& obs,
                         const MapperOptions& options) {
  const bool confident =
      !obs.id.empty() && !obs.id.partial() && obs.id.confidence() >= options.id_confidence_min;
  if (confident) {
    const auto owner = state.id_owner.find(obs.id.best());
    if (owner != state.id_owner.end() && state.slots[owner->second.first].alive) {
      const double d = (state.slots[owner->second.first].Corner(0) - predicted_corner0).norm();
      if (d <= options.id_search_radius_m) return owner->second.first;
    }
  }
  int chosen = -1;
  double best_chi2 = options.null_chi2;
  for (const Candidate& c : candidates) {
    if (c.entrance_distance_m <= options.nn_search_radius_m && c.chi2 < best_chi2) {
      best_chi2 = c.chi2;
      chosen = c.slot;
    }
  }
  return chosen;
}

}  // namespace

double SlotAngle(const SlotObservation& obs) {
  const Eigen::Vector2d entrance = obs.corners_vehicle[1] - obs.corners_vehicle[0];
  const Eigen::Vector2d side = obs.corners_vehicle[3] - obs.corners_vehicle[0];
  return std::atan2(entrance.x() * side.y() - entrance.y() * side.x(), entrance.dot(side));
}

bool PlausibleSlot(const SlotObservation& obs) {
  const double angle = SlotAngle(obs);
  bool finite = true;
  for (const Eigen::Vector2d& c : obs.corners_vehicle) finite &= c.allFinite();
  return finite && angle > kMinSlotAngleRad && angle < kPi - kMinSlotAngleRad &&
         (obs.corners_vehicle[1] - obs.corners_vehicle[0]).norm() > kMinSlotSide_m &&
         (obs.corners_vehicle[3] - obs.corners_vehicle[0]).norm() > kMinSlotSide_m;
}

double CornerSigma(const SlotObservation& obs, int j, const MapperOptions& o) {
  return obs.corner_observed[j] ? std::max(obs.corner_sigma_m, o.min_corner_sigma_m)
                                : o.guessed_corner_sigma_m;
}

double IdSupport(const SlotLandmark& slot, const SlotObservation& obs,
                 const MapperOptions& options) {
  double total = 0.0;
  for (const auto& [id, votes] : slot.votes) total += votes;
  if (total <= 0.0) return 0.0;
  double support = 0.0;
  for (const IdHypothesis& h : FullIdHypotheses(obs.id, options.id_hypothesis_min)) {
    const auto it = slot.votes.find(h.id);
    if (it != slot.votes.end()) support += h.probability * it->second / total;
  }
  const std::string pattern = PartialPattern(obs.id);
  if (!pattern.empty()) {
    // One digit read: the slot's IDs that agree with it, at the read digit's
    // confidence.
    for (const auto& [id, votes] : slot.votes) {
      if (MatchesPattern(id, pattern)) support += obs.id.confidence() * votes / total;
    }
  }
  return std::min(support, 1.0);
}

SlotAssociation AssociateSlot(const MapState& state, int keyframe, const SlotObservation& obs,
                              double prediction_sigma_m, const MapperOptions& options) {
  const SE2 pose = state.PoseOf(keyframe);
  std::array<Eigen::Vector2d, kSlotCorners> predicted;
  for (int j = 0; j < kSlotCorners; ++j) predicted[j] = pose * obs.corners_vehicle[j];
  const std::vector<Candidate> candidates =
      Candidates(state, predicted, obs, prediction_sigma_m, options);

  SlotAssociation association;
  SlotRecord& record = association.record;
  record.keyframe = keyframe;
  record.observation = obs;
  if (options.robust == RobustMode::kNone) {
    const int chosen = ChooseWithoutMixture(state, candidates, predicted[0], obs, options);
    if (chosen < 0) {
      association.new_slot = true;
      return association;
    }
    record.candidates = {chosen};
    record.weights = {1.0};
    record.chosen = chosen;
    return association;
  }
  const double null_cost = -std::log(options.null_weight) + 0.5 * options.null_chi2;
  if (candidates.empty() || candidates.front().cost > null_cost) {
    // Neither a confident ID nor a neighbour: a new slot, added lazily
    // under a temporary ID (paper III-C).
    association.new_slot = true;
    return association;
  }
  for (const Candidate& c : candidates) {
    record.candidates.push_back(c.slot);
    record.weights.push_back(c.weight);
  }
  record.has_null = true;
  record.chosen = candidates.front().slot;
  return association;
}

}  // namespace parkslam::mapping
