#ifndef PARKSLAM_MAPPING_SLOT_ID_H_
#define PARKSLAM_MAPPING_SLOT_ID_H_

// Slot-ID readings as association evidence (paper III-C): the full IDs a
// reading may mean, with their probabilities, and the pattern of a partial
// reading ("3?": one of two digits read).

#include <string>
#include <vector>

#include "parkslam/sensor/sensor_data.h"

namespace parkslam::mapping {

struct IdHypothesis {
  std::string id;
  double probability = 0.0;
};

// The full IDs a reading may mean, most probable first: every combination of
// the per-digit hypotheses, each with the product of its digits'
// probabilities, those of at least min_probability, at most max_count.
// Empty for an empty or partial reading.
std::vector<IdHypothesis> FullIdHypotheses(const SlotIdReading& reading, double min_probability,
                                           int max_count = 8);

// "3?" for a partial reading ('?' for each unread digit), "" otherwise.
std::string PartialPattern(const SlotIdReading& reading);

// True when id has the pattern's length and agrees with it wherever the
// pattern has a digit.
bool MatchesPattern(const std::string& id, const std::string& pattern);

}  // namespace parkslam::mapping

#endif  // PARKSLAM_MAPPING_SLOT_ID_H_
