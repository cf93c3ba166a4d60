#include "parkslam/localization/localization_run.h"

#include <algorithm>
#include <chrono>

namespace parkslam::localization {

SlotCoverage MeasureSlotCoverage(const std::vector<LocalizationEstimate>& estimates,
                                 const SemanticMap& map, double radius_m) {
  SlotCoverage coverage;
  for (const LocalizationEstimate& e : estimates) {
    if (e.state != LocalizerState::kTracking) continue;
    const Eigen::Vector2d p = e.T_map_vehicle.translation();
    const bool near = std::any_of(map.slots.begin(), map.slots.end(), [&](const MapSlot& slot) {
      return (slot.corners_map[0] - p).norm() <= radius_m ||
             (slot.corners_map[1] - p).norm() <= radius_m;
    });
    if (!near) continue;
    ++coverage.frames_near;
    if (e.slots.used > 0) ++coverage.frames_used;
  }
  return coverage;
}

LocalizationRun RunLocalization(SensorSource& source, Localizer* localizer,
                                const std::function<void(TimeNs)>& on_event) {
  LocalizationRun run;
  LocalizerState previous = localizer->state();
  TimeNs last_frame_ns = 0;
  while (const std::optional<SensorEvent> event = source.Next()) {
    if (on_event) on_event(EventTime(*event));
    const auto start = std::chrono::steady_clock::now();
    const std::optional<LocalizationEstimate> estimate = localizer->Process(*event);
    if (!estimate) continue;
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    run.slots += estimate->slots;
    run.tags += estimate->tags;
    if (run.frames > 0 && estimate->t_ns == last_frame_ns) {
      // The same camera frame's other landmark class.
      LocalizationEstimate& frame = run.estimates.back();
      const LocalizationEstimate earlier = frame;
      frame = *estimate;
      frame.slots += earlier.slots;
      frame.tags += earlier.tags;
      frame.relocalized = frame.relocalized || earlier.relocalized;
      run.update_ms.back() += ms;
    } else {
      run.estimates.push_back(*estimate);
      run.update_ms.push_back(ms);
      ++run.frames;
    }
    last_frame_ns = estimate->t_ns;
    run.relocalizations += estimate->relocalized ? 1 : 0;
    if (estimate->state == LocalizerState::kLost && previous != LocalizerState::kLost) {
      ++run.lost_events;
    }
    previous = estimate->state;
    if (estimate->state == LocalizerState::kTracking) {
      AppendOrReplaceLast(&run.tracked, {estimate->t_ns, estimate->T_map_vehicle});
    }
  }
  return run;
}

}  // namespace parkslam::localization
