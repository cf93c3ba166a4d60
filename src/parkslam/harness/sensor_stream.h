#ifndef PARKSLAM_HARNESS_SENSOR_STREAM_H_
#define PARKSLAM_HARNESS_SENSOR_STREAM_H_

// The one place that assembles a sensor stream from a dataset, for every
// command, test and benchmark that replays one: the dataset's log, with
// its slot and tag frames taken from one of three places (a typed choice),
// and optionally with injected faults.
//
//   log ─┬─────────────────────────────────────────► faults? ─► source()
//        └─► camera frames (recorded | rendered) ─► faults? ─► front end ─►

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "parkslam/common/trajectory.h"
#include "parkslam/harness/fault_injection.h"
#include "parkslam/localization/localizer.h"
#include "parkslam/perception/front_end.h"
#include "parkslam/sensor/sensor_log.h"
#include "parkslam/sim/scenario_config.h"

namespace parkslam::io {
struct Dataset;
}

namespace parkslam::harness {

class LiveCameras;

// The log's own observation-level slot and tag frames.
struct FromObservations {};
// The recorded images in dataset_dir/images/ (with their rig,
// images/rig.yaml) through the perception front end.
struct FromRecordedImages {
  std::filesystem::path dataset_dir;
};
// Frame sets rendered on the fly along the true trajectory in the
// simulated world, through the front end; nothing is written.
struct FromLiveRendering {
  double rate_hz = 10.0;
};
using FrameSource = std::variant<FromObservations, FromRecordedImages, FromLiveRendering>;

// "observations", "recorded images in DIR" or "live rendering at R Hz".
std::string Describe(const FrameSource& frames);

struct StreamOptions {
  FrameSource frames;
  // The front end's options, on pixels.
  perception::PerceptionOptions perception;
  // Injected into what the sensors give: the log, or the log with the
  // camera frames, before the front end.
  std::vector<SensorFault> faults;
};

// What a stream is built over. The log is needed always; live rendering
// also needs the scenario (its world) and the true trajectory. Referenced
// data must outlive the stream.
struct StreamInputs {
  std::string name;  // for error messages
  std::uint64_t seed = 0;
  const SensorLog* log = nullptr;
  const sim::ScenarioConfig* scenario = nullptr;  // null: a recording
  const Trajectory* truth = nullptr;              // null or empty: none

  static StreamInputs Of(const io::Dataset& dataset);
};

class SensorStream {
 public:
  // Throws std::runtime_error naming the dataset where the choice cannot
  // be made from its inputs (live rendering of a recording, or without
  // ground truth; recorded images that are missing).
  SensorStream(const StreamInputs& inputs, const StreamOptions& options);
  SensorStream(const io::Dataset& dataset, const StreamOptions& options);
  ~SensorStream();
  SensorStream(const SensorStream&) = delete;
  SensorStream& operator=(const SensorStream&) = delete;

  SensorSource& source();

  // What was injected and which cameras the front end found black or
  // frozen; "" when nothing was.
  std::string DescribeFaults() const;
  // What was injected; null without faults.
  const InjectedFaults* injected() const;
  // The front end's running totals on pixels; null on observations.
  const perception::PerceptionSource* perception() const;
  // On pixels, while `localizer` (fed from source()) tracks, each frame's
  // tags are looked for only where its map has them
  // (perception::TagWindowOptions), as the live API does; nothing changes
  // on observations. The localizer must outlive the stream's use.
  void SearchTagsFor(const localization::Localizer& localizer);

 private:
  struct Pixels;
  SensorSource& WithFaults(SensorSource& inner, std::uint64_t seed,
                           const std::vector<SensorFault>& faults);

  SensorLogSource log_;
  std::unique_ptr<Pixels> pixels_;
  std::unique_ptr<FaultInjectingSource> faults_;
};

}  // namespace parkslam::harness

#endif  // PARKSLAM_HARNESS_SENSOR_STREAM_H_
