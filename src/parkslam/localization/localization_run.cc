#include "parkslam/localization/localization_run.h"

#include <chrono>

namespace parkslam::localization {

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
    run.update_ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count());
    run.estimates.push_back(*estimate);
    if (run.frames == 0 || estimate->t_ns != last_frame_ns) ++run.frames;
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
