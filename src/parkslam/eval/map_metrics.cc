#include "parkslam/eval/map_metrics.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>
#include <unordered_map>

#include "parkslam/common/alignment.h"

namespace parkslam::eval {
namespace {

// A correspondence by identity agrees with an initial-guess hypothesis when
// the aligned map point lies this close to the truth point.
constexpr double kInitialInlierRadiusM = 1.0;
// Up to this many correspondences every pair is a hypothesis; above it, every
// pair of an evenly spaced subset of this size (deterministic).
constexpr std::size_t kMaxRansacCorrespondences = 200;
// Two points closer than this define the rotation too poorly to try.
constexpr double kMinPairSeparationM = 1.0;
// Rounds of "match slots, re-align on their corners".
constexpr int kAlignmentIterations = 3;
// Rounds of "refit on the inliers, recount them" after RANSAC.
constexpr int kInlierRefinements = 2;

struct Correspondence {
  Eigen::Vector2d p_map;
  Eigen::Vector2d p_truth;
};

Eigen::Vector2d EntranceMidpoint(const MapSlot& slot) {
  return 0.5 * (slot.corners_map[0] + slot.corners_map[1]);
}

bool HasPermanentId(const MapSlot& slot) { return !slot.id.empty() && !slot.temporary; }

// Tags with equal IDs (centres) and slots with equal permanent IDs (entrance
// midpoints). A truth ID that appears twice pairs with its first occurrence.
std::vector<Correspondence> IdentityCorrespondences(const SemanticMap& map,
                                                    const SemanticMap& truth) {
  std::vector<Correspondence> correspondences;
  std::unordered_map<int, std::size_t> truth_tag_by_id;
  for (std::size_t j = 0; j < truth.tags.size(); ++j) {
    truth_tag_by_id.emplace(truth.tags[j].tag_id, j);
  }
  for (const MapTag& tag : map.tags) {
    const auto it = truth_tag_by_id.find(tag.tag_id);
    if (it == truth_tag_by_id.end()) continue;
    correspondences.push_back({tag.p_map, truth.tags[it->second].p_map});
  }
  std::unordered_map<std::string, std::size_t> truth_slot_by_id;
  for (std::size_t j = 0; j < truth.slots.size(); ++j) {
    if (HasPermanentId(truth.slots[j])) truth_slot_by_id.emplace(truth.slots[j].id, j);
  }
  for (const MapSlot& slot : map.slots) {
    if (!HasPermanentId(slot)) continue;
    const auto it = truth_slot_by_id.find(slot.id);
    if (it == truth_slot_by_id.end()) continue;
    correspondences.push_back({EntranceMidpoint(slot), EntranceMidpoint(truth.slots[it->second])});
  }
  return correspondences;
}

// Indices of the correspondences that T brings within kInitialInlierRadiusM,
// and the sum of their squared residuals.
std::vector<std::size_t> Inliers(const SE2& T_truth_map,
                                 const std::vector<Correspondence>& correspondences,
                                 double* squared_residual_sum) {
  std::vector<std::size_t> inliers;
  double sum = 0.0;
  constexpr double kRadiusSquared = kInitialInlierRadiusM * kInitialInlierRadiusM;
  for (std::size_t i = 0; i < correspondences.size(); ++i) {
    const double squared =
        (T_truth_map * correspondences[i].p_map - correspondences[i].p_truth).squaredNorm();
    if (squared < kRadiusSquared) {
      inliers.push_back(i);
      sum += squared;
    }
  }
  *squared_residual_sum = sum;
  return inliers;
}

SE2 AlignOn(const std::vector<Correspondence>& correspondences,
            const std::vector<std::size_t>& indices) {
  std::vector<Eigen::Vector2d> source, target;
  source.reserve(indices.size());
  target.reserve(indices.size());
  for (const std::size_t i : indices) {
    source.push_back(correspondences[i].p_map);
    target.push_back(correspondences[i].p_truth);
  }
  return AlignPointSets(source, target);
}

// RANSAC over pairs of correspondences: each pair fixes an SE(2) transform;
// the one with the most inliers (ties: the smaller residual, then the first
// tried) wins and is refitted on its inliers. Identity when no pair yields
// at least 2 inliers.
SE2 InitialAlignment(const std::vector<Correspondence>& correspondences) {
  const std::size_t n = correspondences.size();
  if (n < 2) return SE2();
  std::vector<std::size_t> sample;
  const std::size_t sample_size = std::min(n, kMaxRansacCorrespondences);
  sample.reserve(sample_size);
  for (std::size_t k = 0; k < sample_size; ++k) sample.push_back(k * n / sample_size);

  std::size_t best_inliers = 0;
  double best_residual = std::numeric_limits<double>::infinity();
  SE2 best;
  for (std::size_t a = 0; a < sample.size(); ++a) {
    const Correspondence& ca = correspondences[sample[a]];
    for (std::size_t b = a + 1; b < sample.size(); ++b) {
      const Correspondence& cb = correspondences[sample[b]];
      const double separation_map_m = (cb.p_map - ca.p_map).norm();
      const double separation_truth_m = (cb.p_truth - ca.p_truth).norm();
      // A rigid transform keeps distances: a pair whose distances differ by
      // more than two inlier radii cannot be a pair of inliers.
      if (separation_map_m < kMinPairSeparationM ||
          std::abs(separation_map_m - separation_truth_m) > 2.0 * kInitialInlierRadiusM) {
        continue;
      }
      const SE2 T = AlignPointSets({ca.p_map, cb.p_map}, {ca.p_truth, cb.p_truth});
      double residual = 0.0;
      const std::size_t count = Inliers(T, correspondences, &residual).size();
      if (count > best_inliers || (count == best_inliers && residual < best_residual)) {
        best_inliers = count;
        best_residual = residual;
        best = T;
      }
    }
  }
  if (best_inliers < 2) return SE2();

  for (int round = 0; round < kInlierRefinements; ++round) {
    double residual = 0.0;
    const std::vector<std::size_t> inliers = Inliers(best, correspondences, &residual);
    if (inliers.size() < 2) break;
    best = AlignOn(correspondences, inliers);
  }
  return best;
}

struct SlotMatching {
  std::vector<int> truth_of_map;  // per map slot: matched truth slot, or -1
  std::vector<int> map_of_truth;  // per truth slot: matched map slot, or -1
  int matches = 0;
};

// One-to-one, greedy by increasing distance, below radius_m.
SlotMatching MatchSlots(const std::vector<Eigen::Vector2d>& map_midpoints_truth,
                        const std::vector<Eigen::Vector2d>& truth_midpoints, double radius_m) {
  std::vector<std::tuple<double, int, int>> candidates;  // distance, map, truth
  for (std::size_t i = 0; i < map_midpoints_truth.size(); ++i) {
    for (std::size_t j = 0; j < truth_midpoints.size(); ++j) {
      const double distance_m = (map_midpoints_truth[i] - truth_midpoints[j]).norm();
      if (distance_m < radius_m) {
        candidates.emplace_back(distance_m, static_cast<int>(i), static_cast<int>(j));
      }
    }
  }
  std::sort(candidates.begin(), candidates.end());
  SlotMatching matching;
  matching.truth_of_map.assign(map_midpoints_truth.size(), -1);
  matching.map_of_truth.assign(truth_midpoints.size(), -1);
  for (const auto& [distance_m, i, j] : candidates) {
    if (matching.truth_of_map[i] >= 0 || matching.map_of_truth[j] >= 0) continue;
    matching.truth_of_map[i] = j;
    matching.map_of_truth[j] = i;
    ++matching.matches;
  }
  return matching;
}

// The rigid transform that best lays the corners of the matched map slots on
// those of their truth slots (corners index by index). Only the corners the
// map saw: a guessed back line off by the spread of real depths, the same
// way along a whole row, would pull the alignment and so every other error
// (all corners where the map saw none).
SE2 AlignOnMatchedCorners(const SemanticMap& map, const SemanticMap& truth,
                          const SlotMatching& matching) {
  std::vector<Eigen::Vector2d> source, target, guessed_source, guessed_target;
  for (std::size_t i = 0; i < map.slots.size(); ++i) {
    const int j = matching.truth_of_map[i];
    if (j < 0) continue;
    for (int c = 0; c < kSlotCorners; ++c) {
      const bool seen = map.slots[i].corner_observed[c];
      (seen ? source : guessed_source).push_back(map.slots[i].corners_map[c]);
      (seen ? target : guessed_target).push_back(truth.slots[j].corners_map[c]);
    }
  }
  if (source.size() < 2) {
    source.insert(source.end(), guessed_source.begin(), guessed_source.end());
    target.insert(target.end(), guessed_target.begin(), guessed_target.end());
  }
  return AlignPointSets(source, target);
}

std::vector<Eigen::Vector2d> Midpoints(const SemanticMap& map, const SE2& T) {
  std::vector<Eigen::Vector2d> midpoints;
  midpoints.reserve(map.slots.size());
  for (const MapSlot& slot : map.slots) midpoints.push_back(T * EntranceMidpoint(slot));
  return midpoints;
}

// Right: the legible painted ID, read as such; a temporary ID where the
// truth has no legible ID; or the painted ID read right where the truth
// calls the paint worn (a reader may still make out worn paint).
bool IdIsRight(const MapSlot& map_slot, const MapSlot& truth_slot) {
  const bool read_as_painted =
      !truth_slot.id.empty() && !map_slot.temporary && map_slot.id == truth_slot.id;
  if (read_as_painted) return true;
  const bool truth_legible = !truth_slot.id.empty() && truth_slot.id_legible;
  return !truth_legible && map_slot.temporary;
}

// chi2_2 at the 1-D 2-sigma probability erf(2 / sqrt(2)) = 0.9545:
// -2 ln(1 - 0.9545).
constexpr double kChi2TwoSigma2d = 6.1801;

struct CornerErrorSums {
  int count = 0, within = 0;
  double squared_sum = 0.0, max_m = 0.0;
  void Add(double error_m, double sigma_m) {
    ++count;
    squared_sum += error_m * error_m;
    max_m = std::max(max_m, error_m);
    if (sigma_m > 0.0 && error_m * error_m < kChi2TwoSigma2d * sigma_m * sigma_m) ++within;
  }
  CornerErrors Result() const {
    CornerErrors e;
    e.count = count;
    if (count == 0) return e;
    e.rmse_m = std::sqrt(squared_sum / count);
    e.max_m = max_m;
    e.within_2sigma = static_cast<double>(within) / count;
    return e;
  }
};

void Validate(const SemanticMap& truth, const MapMetricsOptions& options) {
  if (!std::isfinite(options.match_radius_m) || options.match_radius_m <= 0.0) {
    throw std::invalid_argument("EvaluateMap: match_radius_m must be positive and finite, got " +
                                std::to_string(options.match_radius_m));
  }
  if (!options.truth_slot_mask.empty() && options.truth_slot_mask.size() != truth.slots.size()) {
    throw std::invalid_argument(
        "EvaluateMap: truth_slot_mask has " + std::to_string(options.truth_slot_mask.size()) +
        " flags but the truth has " + std::to_string(truth.slots.size()) + " slots");
  }
}

void AddTagMetrics(const SemanticMap& map, const SemanticMap& truth, MapMetrics* metrics) {
  std::unordered_map<int, std::vector<std::size_t>> map_tags_by_id;
  for (std::size_t i = 0; i < map.tags.size(); ++i) {
    map_tags_by_id[map.tags[i].tag_id].push_back(i);
  }
  metrics->tags_true = static_cast<int>(truth.tags.size());
  for (const auto& [id, indices] : map_tags_by_id) {
    const bool in_truth = std::any_of(truth.tags.begin(), truth.tags.end(),
                                      [id = id](const MapTag& t) { return t.tag_id == id; });
    if (!in_truth) metrics->tags_not_in_truth += static_cast<int>(indices.size());
  }
  double squared_sum = 0.0;
  for (const MapTag& truth_tag : truth.tags) {
    const auto it = map_tags_by_id.find(truth_tag.tag_id);
    if (it == map_tags_by_id.end()) continue;
    // Several map tags with one ID: the nearest is the match.
    double best_squared = std::numeric_limits<double>::infinity();
    for (const std::size_t i : it->second) {
      best_squared = std::min(
          best_squared, (metrics->T_truth_map * map.tags[i].p_map - truth_tag.p_map).squaredNorm());
    }
    ++metrics->tags_matched;
    squared_sum += best_squared;
  }
  if (metrics->tags_matched > 0) {
    metrics->tag_rmse_m = std::sqrt(squared_sum / metrics->tags_matched);
  }
}

// The map onto the truth: from the slots' shared IDs, then refined on the
// corners of the slots matched by position.
SE2 AlignMapOnTruth(const SemanticMap& map, const SemanticMap& truth,
                    const std::vector<Eigen::Vector2d>& truth_midpoints, double match_radius_m) {
  SE2 T_truth_map = InitialAlignment(IdentityCorrespondences(map, truth));
  for (int round = 0; round < kAlignmentIterations; ++round) {
    const SlotMatching matching =
        MatchSlots(Midpoints(map, T_truth_map), truth_midpoints, match_radius_m);
    if (matching.matches == 0) break;
    T_truth_map = AlignOnMatchedCorners(map, truth, matching);
  }
  return T_truth_map;
}

// Truth side: matched or missed, corner errors, IDs.
void AddTruthSlotMetrics(const SemanticMap& map, const SemanticMap& truth,
                         const MapMetricsOptions& options, const SlotMatching& matching,
                         MapMetrics* out) {
  MapMetrics& metrics = *out;
  const auto counts = [&options](std::size_t j) {
    return options.truth_slot_mask.empty() || options.truth_slot_mask[j];
  };
  const SE2& T = metrics.T_truth_map;
  int ids_right = 0;
  int temporary_ids = 0;
  double corner_squared_sum = 0.0;
  CornerErrorSums observed, unobserved;
  for (std::size_t j = 0; j < truth.slots.size(); ++j) {
    const int i = matching.map_of_truth[j];
    if (!counts(j)) {
      if (i >= 0) metrics.map_slots[i] = {SlotVerdict::kNotCounted, static_cast<int>(j)};
      continue;
    }
    ++metrics.slots_true;
    if (i < 0) {
      ++metrics.slots_missed;
      metrics.missed_truth_slots.push_back(static_cast<int>(j));
      continue;
    }
    ++metrics.slots_matched;
    const MapSlot& map_slot = map.slots[i];
    const MapSlot& truth_slot = truth.slots[j];
    MapSlotVerdict verdict;
    verdict.verdict = SlotVerdict::kMatched;
    verdict.truth_slot = static_cast<int>(j);
    double slot_squared_sum = 0.0;
    for (int c = 0; c < kSlotCorners; ++c) {
      const double error_m = (T * map_slot.corners_map[c] - truth_slot.corners_map[c]).norm();
      verdict.corner_error_m[c] = error_m;
      slot_squared_sum += error_m * error_m;
      metrics.slot_corner_max_m = std::max(metrics.slot_corner_max_m, error_m);
      (map_slot.corner_observed[c] ? observed : unobserved)
          .Add(error_m, map_slot.corner_sigma_m[c]);
    }
    corner_squared_sum += slot_squared_sum;
    verdict.corner_rms_m = std::sqrt(slot_squared_sum / kSlotCorners);
    verdict.id_right = IdIsRight(map_slot, truth_slot);
    verdict.id_worn_read = verdict.id_right && !map_slot.temporary && !truth_slot.id_legible;
    if (verdict.id_right) ++ids_right;
    if (verdict.id_worn_read) ++metrics.ids_worn_read;
    if (map_slot.temporary) ++temporary_ids;
    metrics.map_slots[i] = verdict;
  }
  metrics.observed_corners = observed.Result();
  metrics.unobserved_corners = unobserved.Result();
  if (metrics.slots_matched > 0) {
    const double matched = metrics.slots_matched;
    metrics.slot_corner_rmse_m = std::sqrt(corner_squared_sum / (kSlotCorners * matched));
    metrics.id_accuracy = ids_right / matched;
    metrics.temporary_id_share = temporary_ids / matched;
  }
}

// Map side: an unmatched map slot near a truth slot duplicates that slot
// (which the greedy matching has necessarily given a nearer map slot); far
// from all truth slots it is spurious.
void AddUnmatchedMapSlots(const SemanticMap& map, const SemanticMap& truth,
                          const MapMetricsOptions& options, const SlotMatching& matching,
                          const std::vector<Eigen::Vector2d>& map_midpoints_truth,
                          const std::vector<Eigen::Vector2d>& truth_midpoints, MapMetrics* out) {
  MapMetrics& metrics = *out;
  const auto counts = [&options](std::size_t j) {
    return options.truth_slot_mask.empty() || options.truth_slot_mask[j];
  };
  for (std::size_t i = 0; i < map.slots.size(); ++i) {
    if (matching.truth_of_map[i] >= 0) continue;
    int nearest = -1;
    double nearest_m = options.match_radius_m;
    for (std::size_t j = 0; j < truth.slots.size(); ++j) {
      const double distance_m = (map_midpoints_truth[i] - truth_midpoints[j]).norm();
      if (distance_m < nearest_m) {
        nearest_m = distance_m;
        nearest = static_cast<int>(j);
      }
    }
    if (nearest < 0) {
      ++metrics.slots_spurious;
      metrics.map_slots[i] = {SlotVerdict::kSpurious, -1};
    } else if (counts(static_cast<std::size_t>(nearest))) {
      ++metrics.slots_duplicate;
      metrics.map_slots[i] = {SlotVerdict::kDuplicate, nearest};
    } else {
      metrics.map_slots[i] = {SlotVerdict::kNotCounted, nearest};
    }
  }
}

}  // namespace

MapMetrics EvaluateMap(const SemanticMap& map, const SemanticMap& truth,
                       const MapMetricsOptions& options) {
  Validate(truth, options);
  const std::vector<Eigen::Vector2d> truth_midpoints = Midpoints(truth, SE2());

  MapMetrics metrics;
  if (options.align) {
    metrics.T_truth_map = AlignMapOnTruth(map, truth, truth_midpoints, options.match_radius_m);
  }
  const SE2& T = metrics.T_truth_map;
  const std::vector<Eigen::Vector2d> map_midpoints_truth = Midpoints(map, T);
  const SlotMatching matching =
      MatchSlots(map_midpoints_truth, truth_midpoints, options.match_radius_m);
  metrics.map_slots.assign(map.slots.size(), MapSlotVerdict{});
  AddTruthSlotMetrics(map, truth, options, matching, &metrics);
  AddUnmatchedMapSlots(map, truth, options, matching, map_midpoints_truth, truth_midpoints,
                       &metrics);
  AddTagMetrics(map, truth, &metrics);
  return metrics;
}

}  // namespace parkslam::eval
