#ifndef PARKSLAM_MAPPING_MAPPING_PARTS_TEST_UTIL_H_
#define PARKSLAM_MAPPING_MAPPING_PARTS_TEST_UTIL_H_

// Small map states for the tests of the mapper's parts.

#include <string>

#include "parkslam/mapping/map_state.h"
#include "parkslam/sensor/sensor_data.h"

namespace parkslam::mapping::test_util {

// A certain reading of every digit of `id` ("" reads nothing; '?' leaves a
// digit unread).
inline SlotIdReading Reading(const std::string& id, double probability = 1.0) {
  SlotIdReading reading;
  for (char c : id) {
    DigitReading digit;
    if (c != '?') digit.hypotheses.push_back({c, probability});
    reading.digits.push_back(digit);
  }
  return reading;
}

// A 2.5 m x 5.3 m perpendicular slot whose entrance starts at (x_m, y_m) of
// the vehicle frame, along +x, the slot behind it along +y.
inline SlotObservation SlotAt(double x_m, double y_m, const std::string& id = "") {
  SlotObservation obs;
  obs.corners_vehicle = {Eigen::Vector2d(x_m, y_m), Eigen::Vector2d(x_m + 2.5, y_m),
                         Eigen::Vector2d(x_m + 2.5, y_m + 5.3), Eigen::Vector2d(x_m, y_m + 5.3)};
  obs.id = Reading(id);
  return obs;
}

// One keyframe at the map's origin.
inline MapState StateWithOneKeyframe() {
  MapState state;
  state.keyframes.push_back(Keyframe{});
  return state;
}

}  // namespace parkslam::mapping::test_util

#endif  // PARKSLAM_MAPPING_MAPPING_PARTS_TEST_UTIL_H_
