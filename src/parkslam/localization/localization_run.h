#ifndef PARKSLAM_LOCALIZATION_LOCALIZATION_RUN_H_
#define PARKSLAM_LOCALIZATION_LOCALIZATION_RUN_H_

// Localization over a whole sensor stream (paper IV: the car localizes on
// the map at every camera frame): the one loop that `parkslam localize`,
// `demo` and the tests share.

#include <functional>
#include <vector>

#include "parkslam/common/trajectory.h"
#include "parkslam/localization/localizer.h"
#include "parkslam/sensor/sensor_log.h"

namespace parkslam::localization {

struct LocalizationRun {
  std::vector<LocalizationEstimate> estimates;  // every estimate, in time order
  Trajectory tracked;       // T_map_vehicle while tracking, one pose per camera frame
  int frames = 0;           // camera frames with an estimate (slots and tags of a frame count once)
  int lost_events = 0;      // transitions into kLost
  int relocalizations = 0;  // estimates that (re)localized globally
  std::vector<double> update_ms;  // wall time of each Process() that gave an estimate
};

// Feeds every event of `source` to `localizer` until the source ends.
// on_event, if set, sees each event's time first (for a progress bar).
LocalizationRun RunLocalization(SensorSource& source, Localizer* localizer,
                                const std::function<void(TimeNs)>& on_event = {});

}  // namespace parkslam::localization

#endif  // PARKSLAM_LOCALIZATION_LOCALIZATION_RUN_H_
