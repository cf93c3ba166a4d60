#include "parkslam/eval/detection_metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include "parkslam/common/angles.h"

namespace parkslam::eval {
namespace {

// Truth corner that detected corner k corresponds to when a slot's entrance
// ends are swapped: the entrance ends trade places, and so do the corners
// behind them (2 lies behind 1, 3 behind 0).
constexpr std::array<int, 4> kSwappedCorner = {1, 0, 3, 2};

bool IsPositiveFinite(double value) { return std::isfinite(value) && value > 0.0; }

void CheckOptions(const DetectionMatchOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument(error);
}

// The larger of the two end distances with the ends in the given order, and
// swapped.
std::pair<double, double> EndDistancesPx(const EntranceLine& detected, const EntranceLine& truth) {
  const double given =
      std::max((detected.a_px - truth.a_px).norm(), (detected.b_px - truth.b_px).norm());
  const double swapped =
      std::max((detected.a_px - truth.b_px).norm(), (detected.b_px - truth.a_px).norm());
  return {given, swapped};
}

// One-to-one greedy matching of admissible pairs by increasing distance,
// ties by detected then truth index.
DetectionMatch GreedyMatch(std::vector<DetectionPair> candidates, std::size_t detected_count,
                           std::size_t truth_count) {
  std::sort(candidates.begin(), candidates.end(),
            [](const DetectionPair& l, const DetectionPair& r) {
              return std::tie(l.distance_px, l.detected, l.truth) <
                     std::tie(r.distance_px, r.detected, r.truth);
            });
  DetectionMatch match;
  match.truth_of_detected.assign(detected_count, -1);
  match.detected_of_truth.assign(truth_count, -1);
  for (const DetectionPair& pair : candidates) {
    int& truth_of_detected = match.truth_of_detected[static_cast<std::size_t>(pair.detected)];
    int& detected_of_truth = match.detected_of_truth[static_cast<std::size_t>(pair.truth)];
    if (truth_of_detected >= 0 || detected_of_truth >= 0) continue;
    truth_of_detected = pair.truth;
    detected_of_truth = pair.detected;
    match.pairs.push_back(pair);
  }
  return match;
}

void CheckSizes(const DetectionMatch& match, std::size_t detected_size, std::size_t truth_size,
                const char* what) {
  if (detected_size != match.truth_of_detected.size() ||
      truth_size != match.detected_of_truth.size()) {
    throw std::invalid_argument(std::string(what) + ": expected " +
                                std::to_string(match.truth_of_detected.size()) + " detected and " +
                                std::to_string(match.detected_of_truth.size()) +
                                " true entries (as matched), got " + std::to_string(detected_size) +
                                " and " + std::to_string(truth_size));
  }
}

}  // namespace

bool DetectionMatchOptions::IsValid(std::string* error) const {
  const char* field = nullptr;
  if (!IsPositiveFinite(max_distance_px)) {
    field = "max_distance_px";
  } else if (!IsPositiveFinite(max_direction_difference_rad)) {
    field = "max_direction_difference_rad";
  }
  if (field == nullptr) return true;
  if (error != nullptr) *error = std::string(field) + ": must be positive and finite";
  return false;
}

std::vector<EntranceLine> EntranceLinesOf(const std::vector<LabelledMarkingPoint>& points,
                                          const std::vector<LabelledSlot>& slots) {
  const int count = static_cast<int>(points.size());
  std::vector<EntranceLine> lines;
  lines.reserve(slots.size());
  for (std::size_t i = 0; i < slots.size(); ++i) {
    const LabelledSlot& slot = slots[i];
    if (slot.a < 0 || slot.a >= count || slot.b < 0 || slot.b >= count) {
      throw std::invalid_argument("slot " + std::to_string(i) + ": marking point index " +
                                  std::to_string(slot.a) + " or " + std::to_string(slot.b) +
                                  " out of range (" + std::to_string(count) + " points)");
    }
    lines.push_back(
        {points[static_cast<std::size_t>(slot.a)].px, points[static_cast<std::size_t>(slot.b)].px});
  }
  return lines;
}

double DirectionDifferenceRad(double a_rad, double b_rad) {
  return std::abs(AngleDiff(a_rad, b_rad));
}

bool MarkingPointsMatch(const LabelledMarkingPoint& detected, const LabelledMarkingPoint& truth,
                        const DetectionMatchOptions& options) {
  if (options.require_same_shape && detected.is_t != truth.is_t) return false;
  // NaN compares false, so non-finite input never matches.
  return (detected.px - truth.px).norm() <= options.max_distance_px &&
         DirectionDifferenceRad(detected.direction_rad, truth.direction_rad) <=
             options.max_direction_difference_rad;
}

bool EntranceLinesMatch(const EntranceLine& detected, const EntranceLine& truth,
                        const DetectionMatchOptions& options, bool* swapped) {
  const auto [given_px, swapped_px] = EndDistancesPx(detected, truth);
  const bool given_ok = given_px <= options.max_distance_px;
  const bool swapped_ok = swapped_px <= options.max_distance_px;
  if (swapped != nullptr) *swapped = swapped_ok && (!given_ok || swapped_px < given_px);
  return given_ok || swapped_ok;
}

DetectionMatch MatchMarkingPoints(const std::vector<LabelledMarkingPoint>& detected,
                                  const std::vector<LabelledMarkingPoint>& truth,
                                  const DetectionMatchOptions& options) {
  CheckOptions(options);
  std::vector<DetectionPair> candidates;
  for (std::size_t d = 0; d < detected.size(); ++d) {
    for (std::size_t t = 0; t < truth.size(); ++t) {
      if (!MarkingPointsMatch(detected[d], truth[t], options)) continue;
      candidates.push_back(
          {static_cast<int>(d), static_cast<int>(t), (detected[d].px - truth[t].px).norm(), false});
    }
  }
  return GreedyMatch(std::move(candidates), detected.size(), truth.size());
}

DetectionMatch MatchSlots(const std::vector<EntranceLine>& detected,
                          const std::vector<EntranceLine>& truth,
                          const DetectionMatchOptions& options) {
  CheckOptions(options);
  std::vector<DetectionPair> candidates;
  for (std::size_t d = 0; d < detected.size(); ++d) {
    for (std::size_t t = 0; t < truth.size(); ++t) {
      bool swapped = false;
      if (!EntranceLinesMatch(detected[d], truth[t], options, &swapped)) continue;
      const auto [given_px, swapped_px] = EndDistancesPx(detected[d], truth[t]);
      candidates.push_back(
          {static_cast<int>(d), static_cast<int>(t), swapped ? swapped_px : given_px, swapped});
    }
  }
  return GreedyMatch(std::move(candidates), detected.size(), truth.size());
}

void DetectionCounts::Add(const DetectionMatch& match) {
  true_positives += match.true_positives();
  false_positives += match.false_positives();
  false_negatives += match.false_negatives();
}

void DetectionCounts::Add(const DetectionCounts& other) {
  true_positives += other.true_positives;
  false_positives += other.false_positives;
  false_negatives += other.false_negatives;
}

double DetectionCounts::precision() const {
  const int detections = true_positives + false_positives;
  return detections == 0 ? 1.0 : static_cast<double>(true_positives) / detections;
}

double DetectionCounts::recall() const {
  const int truths = true_positives + false_negatives;
  return truths == 0 ? 1.0 : static_cast<double>(true_positives) / truths;
}

void ErrorAccumulator::Add(double error) {
  ++count;
  sum += error;
  sum_squares += error * error;
  max = std::max(max, error);
}

void ErrorAccumulator::Add(const ErrorAccumulator& other) {
  count += other.count;
  sum += other.sum;
  sum_squares += other.sum_squares;
  max = std::max(max, other.max);
}

double ErrorAccumulator::mean() const { return count == 0 ? 0.0 : sum / count; }

double ErrorAccumulator::rms() const { return count == 0 ? 0.0 : std::sqrt(sum_squares / count); }

void AddSlotCornerErrors(const DetectionMatch& match, const std::vector<SlotCornersPx>& detected,
                         const std::vector<SlotCornersPx>& truth, double pixels_per_m,
                         SlotCornerErrors* errors) {
  CheckSizes(match, detected.size(), truth.size(), "AddSlotCornerErrors");
  if (!IsPositiveFinite(pixels_per_m)) {
    throw std::invalid_argument("AddSlotCornerErrors: pixels_per_m must be positive and finite");
  }
  for (const DetectionPair& pair : match.pairs) {
    const SlotCornersPx& d = detected[static_cast<std::size_t>(pair.detected)];
    const SlotCornersPx& t = truth[static_cast<std::size_t>(pair.truth)];
    for (int k = 0; k < 4; ++k) {
      const int truth_corner = pair.swapped ? kSwappedCorner[static_cast<std::size_t>(k)] : k;
      const double error_m =
          (d[static_cast<std::size_t>(k)] - t[static_cast<std::size_t>(truth_corner)]).norm() /
          pixels_per_m;
      if (k < 2) errors->entrance_m.Add(error_m);
      errors->all_corners_m.Add(error_m);
    }
  }
}

void IdCounts::Add(const IdCounts& other) {
  readable += other.readable;
  correct += other.correct;
  unread += other.unread;
  unreadable += other.unreadable;
  invented += other.invented;
  invented_right += other.invented_right;
}

double IdCounts::accuracy() const {
  return readable == 0 ? 1.0 : static_cast<double>(correct) / readable;
}

void AddIdCounts(const DetectionMatch& match, const std::vector<std::string>& detected_ids,
                 const std::vector<SlotIdTruth>& truth_ids, IdCounts* counts) {
  CheckSizes(match, detected_ids.size(), truth_ids.size(), "AddIdCounts");
  for (const DetectionPair& pair : match.pairs) {
    const std::string& read = detected_ids[static_cast<std::size_t>(pair.detected)];
    const SlotIdTruth& truth = truth_ids[static_cast<std::size_t>(pair.truth)];
    if (truth.readable && !truth.id.empty()) {
      ++counts->readable;
      if (read == truth.id) ++counts->correct;
      if (read.empty()) ++counts->unread;
    } else {
      ++counts->unreadable;
      if (read.empty() || read.find('?') != std::string::npos) continue;
      ++counts->invented;
      if (read == truth.id) ++counts->invented_right;
    }
  }
}

}  // namespace parkslam::eval
