#include "parkslam/mapping/map_state.h"

namespace parkslam::mapping {

void MapState::RebuildRecordIndexes() {
  slot_record_index.assign(slots.size(), {});
  for (size_t r = 0; r < slot_records.size(); ++r) {
    for (int c : slot_records[r].candidates) slot_record_index[static_cast<size_t>(c)].push_back(r);
  }
  tag_record_index.assign(tags.size(), {});
  for (size_t r = 0; r < tag_records.size(); ++r) {
    tag_record_index[static_cast<size_t>(tag_records[r].tag)].push_back(r);
  }
}

}  // namespace parkslam::mapping
