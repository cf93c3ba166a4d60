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
  // One estimate per camera frame, in time order: a frame's slot and tag
  // estimates (the front end gives them as two events of one time) merged,
  // their landmark counts added and the later pose kept.
  std::vector<LocalizationEstimate> estimates;
  Trajectory tracked;       // T_map_vehicle while tracking, one pose per camera frame
  int frames = 0;           // camera frames with an estimate (slots and tags of a frame count once)
  int lost_events = 0;      // transitions into kLost
  int relocalizations = 0;  // estimates that (re)localized globally
  std::vector<double> update_ms;  // wall time of each frame's Process() calls, added
  // What became of each landmark class's observations over the run.
  LandmarkUse slots;
  LandmarkUse tags;
};

// How often slots served where they could: among the frames tracked with
// an entrance corner of a map slot within radius_m of the car (by the
// estimated pose), those in which at least one slot updated the pose.
struct SlotCoverage {
  int frames_near = 0;
  int frames_used = 0;
  double share() const { return frames_near > 0 ? double(frames_used) / frames_near : 0.0; }
};
SlotCoverage MeasureSlotCoverage(const std::vector<LocalizationEstimate>& estimates,
                                 const SemanticMap& map, double radius_m = 5.0);

// Feeds every event of `source` to `localizer` until the source ends.
// on_event, if set, sees each event's time first (for a progress bar).
LocalizationRun RunLocalization(SensorSource& source, Localizer* localizer,
                                const std::function<void(TimeNs)>& on_event = {});

}  // namespace parkslam::localization

#endif  // PARKSLAM_LOCALIZATION_LOCALIZATION_RUN_H_
