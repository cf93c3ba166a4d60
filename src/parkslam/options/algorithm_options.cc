#include "parkslam/options/algorithm_options.h"

#include <string>
#include <utility>

#include "parkslam/common/field_checker.h"
#include "parkslam/options/option_ranges.h"

namespace parkslam {
namespace {

// The front end's own fields (its parts have their checks).
void CheckFrontEnd(const perception::PerceptionOptions& o, FieldChecker& c) {
  c.InRange(o.tag_min_height_m, 0.0, 10.0, "front_end.tag_min_height_m", "m");
  c.InRange(o.tag_max_height_m, o.tag_min_height_m, 10.0, "front_end.tag_max_height_m", "m");
  c.InRange(o.tag_min_range_m, 0.0, 100.0, "front_end.tag_min_range_m", "m");
  c.InRange(o.classical_id_min_confidence, 0.0, 1.0, "front_end.classical_id_min_confidence", "");
  const std::pair<const char*, double> sigmas[] = {
      {"corner_sigma_m", o.corner_sigma_m},
      {"corner_sigma_per_m", o.corner_sigma_per_m},
      {"tag_range_sigma_m", o.tag_range_sigma_m},
      {"tag_range_sigma_per_m", o.tag_range_sigma_per_m},
      {"tag_bearing_sigma_rad", o.tag_bearing_sigma_rad},
      {"tag_yaw_sigma_rad", o.tag_yaw_sigma_rad},
      {"tag_yaw_sigma_per_m", o.tag_yaw_sigma_per_m}};
  for (const auto& [name, sigma] : sigmas) {
    c.PositiveAtMost(sigma, 10.0, std::string("front_end.") + name, "");
  }
}

}  // namespace

bool AlgorithmOptions::IsValid(std::string* error) const {
  // An empty model path means the committed network (perception::PerceptionOptions).
  perception::LearnedSlotDetectorOptions learned_slots = front_end.learned_slots;
  perception::LearnedSlotIdReaderOptions learned_ids = front_end.learned_ids;
  if (learned_slots.model_path.empty()) learned_slots.model_path = "default";
  if (learned_ids.model_path.empty()) learned_ids.model_path = "default";
  // Every number within its plausible range first (option_ranges.h), then
  // each part's relations between its numbers.
  if (!CheckOptionRanges(*this, error)) return false;
  FieldChecker c(error);
  CheckFrontEnd(front_end, c);
  c.Part(front_end.top_view, "front_end.top_view");
  c.Part(front_end.slots, "front_end.slots");
  c.Part(front_end.ids, "front_end.ids");
  c.Part(learned_slots, "front_end.learned_slots");
  c.Part(learned_ids, "front_end.learned_ids");
  c.Part(front_end.tags, "front_end.tags");
  c.Part(front_end.tag_windows, "front_end.tag_windows");
  c.Part(mapper, "mapper");
  c.Part(localizer, "localizer");
  c.Part(follower, "follower");
  return c.ok();
}

}  // namespace parkslam
