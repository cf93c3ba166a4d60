#include "parkslam/harness/sensor_stream.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <string>

#include "parkslam/harness/short_drive_test_util.h"
#include "parkslam/localization/localization_run.h"
#include "parkslam/localization/localizer.h"
#include "parkslam/sim/world.h"

namespace parkslam::harness {
namespace {

using test_util::ShortDrive;

const ShortDrive& StreamDrive() {
  static const ShortDrive d = test_util::MakeShortDrive(5);
  return d;
}

StreamInputs Inputs() {
  const ShortDrive& d = StreamDrive();
  return {"short drive", 5, &d.simulation.log, &d.scenario, &d.truth};
}

// The largest distance of a tracked pose from the truth at its time.
double WorstError(const localization::LocalizationRun& run, const Trajectory& truth) {
  double worst_m = 0.0;
  for (const TimedPose& p : run.tracked) {
    const std::optional<SE2> t = PoseAt(truth, p.t_ns);
    if (!t) return 1e9;
    worst_m = std::max(worst_m, (t->translation() - p.T_map_vehicle.translation()).norm());
  }
  return worst_m;
}

struct EventCounts {
  int slot_frames = 0, tag_frames = 0, camera_frames = 0, others = 0;
};

EventCounts CountEvents(SensorSource& source) {
  EventCounts c;
  TimeNs last = -1;
  while (const auto event = source.Next()) {
    EXPECT_GE(EventTime(*event), last);
    last = EventTime(*event);
    if (std::holds_alternative<SlotObservationFrame>(*event)) {
      ++c.slot_frames;
    } else if (std::holds_alternative<TagObservationFrame>(*event)) {
      ++c.tag_frames;
    } else if (std::holds_alternative<CameraFrame>(*event)) {
      ++c.camera_frames;
    } else {
      ++c.others;
    }
  }
  return c;
}

TEST(SensorStreamTest, OnObservationsIsTheLogItself) {
  const SensorLog& log = StreamDrive().simulation.log;
  SensorStream stream(Inputs(), {FromObservations{}, {}, {}});
  const EventCounts c = CountEvents(stream.source());
  EXPECT_EQ(c.slot_frames, static_cast<int>(log.slot_frames.size()));
  EXPECT_EQ(c.tag_frames, static_cast<int>(log.tag_frames.size()));
  EXPECT_EQ(c.camera_frames, 0);
  EXPECT_GT(c.others, 1000);
  EXPECT_EQ(stream.perception(), nullptr);
  EXPECT_EQ(stream.injected(), nullptr);
  EXPECT_EQ(stream.DescribeFaults(), "");
}

TEST(SensorStreamTest, LiveRenderingReplacesTheObservationsWithWhatTheCamerasSee) {
  SensorStream stream(Inputs(), {FromLiveRendering{0.5}, {}, {}});
  const EventCounts c = CountEvents(stream.source());
  const double duration_s =
      ToSeconds(StreamDrive().truth.back().t_ns - StreamDrive().truth.front().t_ns);
  const int frames = static_cast<int>(duration_s / 2.0) + 1;
  // One slot frame and one tag frame per rendered frame set, nothing else
  // of the log's observation level.
  EXPECT_EQ(c.slot_frames, frames);
  EXPECT_EQ(c.tag_frames, frames);
  EXPECT_EQ(c.camera_frames, 0);
  ASSERT_NE(stream.perception(), nullptr);
  EXPECT_EQ(stream.perception()->frames_processed(), frames);
}

// On pixels, both landmark classes that the front end reports reach the
// localizer: along aisle 1 of the default lot, past tags and slots, on the
// true map from the true start, the slots and the tags the cameras find are
// mostly used, and the pose stays within a few centimetres.
TEST(SensorStreamTest, OnPixelsTheLocalizerUsesSlotsAndTags) {
  const ShortDrive& d = StreamDrive();
  const SemanticMap map = sim::ToSemanticMap(d.simulation.world);
  localization::Localizer localizer(
      map, localization::LocalizerOptions{},
      odometry::EkfOptionsFromSpec(d.scenario.sensors.odometry, d.scenario.vehicle));
  localizer.SetPose(d.truth.front().T_map_vehicle, Eigen::Matrix3d::Identity() * 1e-4);
  SensorStream stream(Inputs(), {FromLiveRendering{2.0}, {}, {}});
  const localization::LocalizationRun run =
      localization::RunLocalization(stream.source(), &localizer);
  ASSERT_GT(run.frames, 50);
  EXPECT_EQ(static_cast<int>(run.tracked.size()), run.frames);
  EXPECT_GT(run.slots.observed, 40);
  EXPECT_GT(run.slots.used, run.slots.observed / 2);
  EXPECT_GT(run.tags.observed, 10);
  EXPECT_GT(run.tags.used, run.tags.observed / 2);
  const double worst_m = WorstError(run, d.truth);
  EXPECT_LT(worst_m, 0.15);
}

// The same in a realistic look (the scene renderer's whole lot: epoxy
// floor, real fonts, parked cars): the slots and tags the front end finds
// still reach the localizer, and the pose stays within 15 cm (as in grey).
TEST(SensorStreamTest, InARealisticLookTheLocalizerStillUsesSlotsAndTags) {
  const ShortDrive& d = StreamDrive();
  sim::ScenarioConfig scenario = d.scenario;
  scenario.world.look = "epoxy";
  const StreamInputs inputs{"short drive", 5, &d.simulation.log, &scenario, &d.truth};
  const SemanticMap map = sim::ToSemanticMap(d.simulation.world);
  localization::Localizer localizer(
      map, localization::LocalizerOptions{},
      odometry::EkfOptionsFromSpec(d.scenario.sensors.odometry, d.scenario.vehicle));
  localizer.SetPose(d.truth.front().T_map_vehicle, Eigen::Matrix3d::Identity() * 1e-4);
  SensorStream stream(inputs, {FromLiveRendering{2.0}, {}, {}});
  const localization::LocalizationRun run =
      localization::RunLocalization(stream.source(), &localizer);
  ASSERT_GT(run.frames, 50);
  EXPECT_EQ(static_cast<int>(run.tracked.size()), run.frames);
  EXPECT_GT(run.slots.used, run.slots.observed / 2);
  EXPECT_GT(run.slots.used, 30);
  EXPECT_GT(run.tags.used, run.tags.observed / 2);
  const double worst_m = WorstError(run, d.truth);
  EXPECT_LT(worst_m, 0.15);  // measured 0.11 m: 156 of 157 slots and 71 of 72 tags used
}

TEST(SensorStreamTest, FaultsAreInjectedAndReported) {
  const std::vector<SensorFault> faults = {ParseSensorFault("wheel-dropout@5+3")};
  SensorStream stream(Inputs(), {FromObservations{}, {}, faults});
  CountEvents(stream.source());
  ASSERT_NE(stream.injected(), nullptr);
  EXPECT_GT(stream.injected()->wheel_samples_dropped, 100);
  EXPECT_NE(stream.DescribeFaults().find("wheel samples dropped"), std::string::npos);
}

TEST(SensorStreamTest, RefusesChoicesItsInputsCannotServe) {
  StreamInputs recording = Inputs();
  recording.scenario = nullptr;
  try {
    SensorStream stream(recording, {FromLiveRendering{5.0}, {}, {}});
    FAIL() << "live rendering of a recording";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("short drive: live images render"), std::string::npos)
        << e.what();
  }
  StreamInputs no_truth = Inputs();
  no_truth.truth = nullptr;
  EXPECT_THROW(SensorStream(no_truth, {FromLiveRendering{5.0}, {}, {}}), std::runtime_error);
  const std::filesystem::path missing = "/nonexistent/parkslam-dataset";
  EXPECT_THROW(SensorStream(Inputs(), {FromRecordedImages{missing}, {}, {}}), std::exception);
}

TEST(SensorStreamTest, DescribesItsChoice) {
  EXPECT_EQ(Describe(FromObservations{}), "observations");
  EXPECT_EQ(Describe(FromLiveRendering{2.5}), "live rendering at 2.5 Hz");
  EXPECT_EQ(Describe(FromRecordedImages{"/data/d1"}), "recorded images in /data/d1/images");
}

}  // namespace
}  // namespace parkslam::harness
