#include "parkslam/options/algorithm_options.h"

#include <cmath>

namespace parkslam {
namespace {

// Runs one part's check and prefixes its message with the part's path.
template <typename T>
bool Check(const T& part, const char* path, std::string* error) {
  std::string message;
  if (part.IsValid(&message)) return true;
  if (error != nullptr) *error = std::string(path) + ": " + message;
  return false;
}

// The front end's own fields (its parts have their checks).
bool CheckFrontEnd(const perception::PerceptionOptions& o, std::string* error) {
  auto fail = [error](const std::string& message) {
    if (error != nullptr) *error = "front_end." + message;
    return false;
  };
  if (!(o.tag_min_height_m >= 0.0 && o.tag_max_height_m >= o.tag_min_height_m &&
        o.tag_max_height_m <= 10.0)) {
    return fail("tag_min_height_m, tag_max_height_m: need 0 <= min <= max <= 10 m");
  }
  if (!(o.tag_min_range_m >= 0.0 && o.tag_min_range_m <= 100.0)) {
    return fail("tag_min_range_m: must be in [0, 100] m");
  }
  const double sigmas[] = {o.corner_sigma_m,        o.corner_sigma_per_m,    o.tag_range_sigma_m,
                           o.tag_range_sigma_per_m, o.tag_bearing_sigma_rad, o.tag_yaw_sigma_rad,
                           o.tag_yaw_sigma_per_m};
  for (double sigma : sigmas) {
    if (!(sigma > 0.0 && sigma <= 10.0)) {
      return fail("corner_sigma_m ... tag_yaw_sigma_per_m: each must be in (0, 10]");
    }
  }
  return true;
}

}  // namespace

bool AlgorithmOptions::IsValid(std::string* error) const {
  // An empty model path means the committed network (perception::PerceptionOptions).
  perception::LearnedSlotDetectorOptions learned_slots = front_end.learned_slots;
  perception::LearnedSlotIdReaderOptions learned_ids = front_end.learned_ids;
  if (learned_slots.model_path.empty()) learned_slots.model_path = "default";
  if (learned_ids.model_path.empty()) learned_ids.model_path = "default";
  return CheckFrontEnd(front_end, error) &&
         Check(front_end.top_view, "front_end.top_view", error) &&
         Check(front_end.slots, "front_end.slots", error) &&
         Check(front_end.ids, "front_end.ids", error) &&
         Check(learned_slots, "front_end.learned_slots", error) &&
         Check(learned_ids, "front_end.learned_ids", error) &&
         Check(front_end.tags, "front_end.tags", error) && Check(mapper, "mapper", error) &&
         Check(localizer, "localizer", error) && Check(follower, "follower", error);
}

}  // namespace parkslam
