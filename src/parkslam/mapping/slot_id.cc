#include "parkslam/mapping/slot_id.h"

#include <algorithm>

namespace parkslam::mapping {

std::vector<IdHypothesis> FullIdHypotheses(const SlotIdReading& reading, double min_probability,
                                           int max_count) {
  if (reading.empty() || reading.partial()) return {};
  std::vector<IdHypothesis> partial_ids{{"", 1.0}};
  for (const DigitReading& digit : reading.digits) {
    std::vector<IdHypothesis> extended;
    for (const IdHypothesis& prefix : partial_ids) {
      for (const DigitHypothesis& h : digit.hypotheses) {
        const double p = prefix.probability * h.probability;
        // Probabilities only shrink as digits are added: prune early.
        if (p >= min_probability) extended.push_back({prefix.id + h.digit, p});
      }
    }
    partial_ids = std::move(extended);
  }
  std::sort(
      partial_ids.begin(), partial_ids.end(), [](const IdHypothesis& a, const IdHypothesis& b) {
        return a.probability > b.probability || (a.probability == b.probability && a.id < b.id);
      });
  if (static_cast<int>(partial_ids.size()) > max_count) partial_ids.resize(max_count);
  return partial_ids;
}

std::string PartialPattern(const SlotIdReading& reading) {
  return reading.partial() ? reading.best() : std::string();
}

bool MatchesPattern(const std::string& id, const std::string& pattern) {
  if (id.size() != pattern.size()) return false;
  for (size_t i = 0; i < id.size(); ++i) {
    if (pattern[i] != '?' && pattern[i] != id[i]) return false;
  }
  return true;
}

}  // namespace parkslam::mapping
