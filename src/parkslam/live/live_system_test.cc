#include "parkslam/live/live_system.h"

#include <gtest/gtest.h>

#include <chrono>
#include <deque>
#include <functional>
#include <thread>

#include "parkslam/common/trajectory.h"
#include "parkslam/harness/live_cameras.h"
#include "parkslam/harness/rendering_source.h"
#include "parkslam/harness/short_drive_test_util.h"
#include "parkslam/odometry/odometry_ekf.h"
#include "parkslam/sensor/sensor_log.h"

namespace parkslam::live {
namespace {

using harness::test_util::ShortDrive;

const ShortDrive& LiveDrive() {
  static const ShortDrive drive = harness::test_util::MakeShortDrive(4);
  return drive;
}

LiveOptions Options() {
  LiveOptions o;
  o.odometry = odometry::EkfOptionsFromSpec(LiveDrive().scenario.sensors.odometry,
                                            LiveDrive().scenario.vehicle);
  return o;
}

// Estimates of one localizer fed `source` as `localize` feeds it; `before`
// sees the localizer first (to let a front end look for tags as it tracks).
std::vector<localization::LocalizationEstimate> Reference(
    SensorSource& source, const SemanticMap& map, const SE2& start,
    const std::function<void(const localization::Localizer&)>& before = {}) {
  localization::Localizer localizer(map, {}, Options().odometry);
  localizer.SetPose(start, Eigen::Vector3d(0.5, 0.5, 0.1).cwiseAbs2().asDiagonal());
  if (before) before(localizer);
  std::vector<localization::LocalizationEstimate> out;
  while (const auto event = source.Next()) {
    if (auto estimate = localizer.Process(*event)) out.push_back(*estimate);
  }
  return out;
}

void ExpectSamePoses(const std::vector<localization::LocalizationEstimate>& a,
                     const std::vector<localization::LocalizationEstimate>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].t_ns, b[i].t_ns) << i;
    EXPECT_LT((a[i].T_map_vehicle.translation() - b[i].T_map_vehicle.translation()).norm(), 1e-3)
        << i;
  }
}

// The lot's map, the true start, and the estimates of a localizer fed the
// drive's slot and tag frames as `localize` feeds them.
struct FramesReference {
  SemanticMap map;
  SE2 start;
  std::vector<localization::LocalizationEstimate> reference;
};

const FramesReference& OnFrames() {
  static const FramesReference r = [] {
    const ShortDrive& d = LiveDrive();
    FramesReference out{sim::ToSemanticMap(d.simulation.world), d.truth.front().T_map_vehicle, {}};
    SensorLogSource source(d.simulation.log);
    out.reference = Reference(source, out.map, out.start);
    return out;
  }();
  return r;
}

TEST(LiveSystemTest, OnSlotAndTagFramesThePosesAreTheLocalizersOwn) {
  const ShortDrive& d = LiveDrive();
  const auto& [map, start, reference] = OnFrames();
  ASSERT_GT(reference.size(), 100u);

  LiveSystem live(map, nullptr, Options(), start);
  SensorLogSource source(d.simulation.log);
  std::vector<localization::LocalizationEstimate> estimates;
  EXPECT_FALSE(live.PredictedPose().has_value());
  while (const auto event = source.Next()) {
    live.Process(*event);
    for (auto& e : live.TakeEstimates()) estimates.push_back(e);
  }
  live.Finish();
  ExpectSamePoses(estimates, reference);
  EXPECT_EQ(live.stats().estimates, static_cast<int>(reference.size()));
  EXPECT_EQ(live.stats().latency_ms.size(), reference.size());
  // The prediction runs ahead of the last estimate by the odometry since.
  const std::optional<TimedPose> predicted = live.PredictedPose();
  ASSERT_TRUE(predicted.has_value());
  EXPECT_GE(predicted->t_ns, estimates.back().t_ns);
  const std::optional<SE2> truth = PoseAt(d.truth, predicted->t_ns);
  ASSERT_TRUE(truth.has_value());
  EXPECT_LT((predicted->T_map_vehicle.translation() - truth->translation()).norm(), 0.1);
  EXPECT_THROW(live.Process(CameraFrame{}), std::invalid_argument);
}

TEST(LiveSystemTest, AnEstimateCallbackGetsEveryEstimateAsItIsMade) {
  const ShortDrive& d = LiveDrive();
  const auto& [map, start, reference] = OnFrames();

  std::vector<localization::LocalizationEstimate> called;
  LiveOptions options = Options();
  options.on_estimate = [&called](const localization::LocalizationEstimate& e) {
    called.push_back(e);
  };
  LiveSystem live(map, nullptr, options, start);
  SensorLogSource source(d.simulation.log);
  while (const auto event = source.Next()) {
    const size_t before = called.size();
    const bool frame = std::holds_alternative<SlotObservationFrame>(*event) ||
                       std::holds_alternative<TagObservationFrame>(*event);
    live.Process(*event);
    // Slot and tag frames are the estimator's at once: the callback has
    // run before Process returns.
    if (frame) {
      EXPECT_EQ(called.size(), before + 1);
    }
    EXPECT_TRUE(live.TakeEstimates().empty());
  }
  live.Finish();
  ExpectSamePoses(called, reference);
}

// Slot and tag frames that come behind a few odometry events newer than
// them (as from transports of their own): with a reorder window the
// estimator still takes them in time order, and gives localize's poses;
// without one its dead reckoning rejects them.
TEST(LiveSystemTest, AReorderWindowTakesFramesThatCameLateInTimeOrder) {
  const ShortDrive& d = LiveDrive();
  const auto& [map, start, reference] = OnFrames();
  // The stream with every slot and tag frame after the next 3 odometry events.
  std::vector<SensorEvent> late;
  std::deque<SensorEvent> frames;
  int since = 0;
  SensorLogSource source(d.simulation.log);
  while (const auto event = source.Next()) {
    const bool frame = std::holds_alternative<SlotObservationFrame>(*event) ||
                       std::holds_alternative<TagObservationFrame>(*event);
    if (frame) {
      frames.push_back(*event);
      since = 0;
      continue;
    }
    late.push_back(*event);
    if (++since == 3) {
      for (auto& f : frames) late.push_back(std::move(f));
      frames.clear();
    }
  }
  for (auto& f : frames) late.push_back(std::move(f));
  for (const double window_s : {0.0, 0.1}) {
    LiveOptions options = Options();
    options.reorder_window_s = window_s;
    LiveSystem live(map, nullptr, options, start);
    std::vector<localization::LocalizationEstimate> estimates;
    for (const SensorEvent& event : late) {
      live.Process(event);
      for (auto& e : live.TakeEstimates()) estimates.push_back(e);
    }
    live.Finish();
    for (auto& e : live.TakeEstimates()) estimates.push_back(e);
    if (window_s > 0.0) {
      ExpectSamePoses(estimates, reference);
    } else {
      EXPECT_LT(estimates.size(), reference.size() / 2);  // most came too late
    }
  }
}

// On pixels, waiting for each frame's perception: the poses of `localize`
// on the same rendered frames, and no frame dropped.
TEST(LiveSystemTest, OnCameraFramesWaitingForPerceptionThePosesAreLocalizesOwn) {
  const ShortDrive& d = LiveDrive();
  const SemanticMap map = sim::ToSemanticMap(d.simulation.world);
  const SE2 start = d.truth.front().T_map_vehicle;
  harness::LiveCameras cameras(sim::BuildWorld(d.scenario.world), d.scenario.world, 4);
  SensorLogSource log_a(d.simulation.log);
  harness::RenderingSource rendered_a(log_a, cameras.renderer(), d.truth, cameras.cameras(), 2.0);
  perception::PerceptionSource perceived(rendered_a, cameras.front_end());
  // As localize's chain: the tags looked for where the map has them.
  const auto reference = Reference(perceived, map, start, [&](const localization::Localizer& l) {
    perceived.SearchTagsIn(
        [&](TimeNs t_ns) { return MapTagWindows(cameras.front_end(), l, t_ns); });
  });
  ASSERT_GT(reference.size(), 40u);

  LiveOptions options = Options();
  options.wait_for_perception = true;
  LiveSystem live(map, &cameras.rig(), options, start);
  SensorLogSource log_b(d.simulation.log);
  harness::RenderingSource rendered_b(log_b, cameras.renderer(), d.truth, cameras.cameras(), 2.0);
  std::vector<localization::LocalizationEstimate> estimates;
  while (const auto event = rendered_b.Next()) {
    // On pixels a car has no slot or tag frames but what its cameras see.
    if (std::holds_alternative<SlotObservationFrame>(*event) ||
        std::holds_alternative<TagObservationFrame>(*event)) {
      continue;
    }
    live.Process(*event);
    for (auto& e : live.TakeEstimates()) estimates.push_back(e);
  }
  live.Finish();
  for (auto& e : live.TakeEstimates()) estimates.push_back(e);
  ExpectSamePoses(estimates, reference);
  EXPECT_EQ(live.stats().frames_dropped, 0);
  EXPECT_EQ(live.stats().frames_perceived, live.stats().camera_frames);
  // The tags were found in windows, and used, on both sides alike.
  const auto tags_used = [](const std::vector<localization::LocalizationEstimate>& e) {
    int n = 0;
    for (const auto& x : e) n += x.tags.used;
    return n;
  };
  EXPECT_GT(tags_used(reference), 5);
  EXPECT_EQ(tags_used(estimates), tags_used(reference));
  EXPECT_GT(live.stats().tag_searches_in_windows, live.stats().camera_frames / 2);
}

// Frames faster than the perception, never waiting: the frames that waited
// are dropped and counted, the estimates stay in time order and on the car.
TEST(LiveSystemTest, FramesFasterThanPerceptionAreDroppedAndTheCarIsStillTracked) {
  const ShortDrive& d = LiveDrive();
  const SemanticMap map = sim::ToSemanticMap(d.simulation.world);
  harness::LiveCameras cameras(sim::BuildWorld(d.scenario.world), d.scenario.world, 4);
  SensorLogSource log(d.simulation.log);
  harness::RenderingSource rendered(log, cameras.renderer(), d.truth, cameras.cameras(), 2.0);
  std::vector<SensorEvent> events;
  while (auto event = rendered.Next()) {
    if (std::holds_alternative<SlotObservationFrame>(*event) ||
        std::holds_alternative<TagObservationFrame>(*event)) {
      continue;
    }
    events.push_back(std::move(*event));
  }
  LiveSystem live(map, &cameras.rig(), Options(), d.truth.front().T_map_vehicle);
  std::vector<localization::LocalizationEstimate> estimates;
  for (SensorEvent& event : events) {
    const bool frame = std::holds_alternative<CameraFrame>(event);
    live.Process(std::move(event));
    // Three frame sets come within one perception (about 15 ms each).
    if (frame) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    for (auto& e : live.TakeEstimates()) estimates.push_back(e);
  }
  live.Finish();
  for (auto& e : live.TakeEstimates()) estimates.push_back(e);
  const LiveStats& st = live.stats();
  EXPECT_GT(st.frames_dropped, 0);
  EXPECT_EQ(st.frames_perceived + st.frames_dropped, st.camera_frames);
  ASSERT_GT(estimates.size(), 10u);
  for (size_t i = 1; i < estimates.size(); ++i) EXPECT_LE(estimates[i - 1].t_ns, estimates[i].t_ns);
  const localization::LocalizationEstimate& last = estimates.back();
  const std::optional<SE2> truth = PoseAt(d.truth, last.t_ns);
  ASSERT_TRUE(truth.has_value());
  EXPECT_LT((last.T_map_vehicle.translation() - truth->translation()).norm(), 0.3);
}

// Mapping live: the map grows along the drive, and the pose and the map are
// those of a mapper fed the same drive (waiting for the background solve,
// as wait_for_perception asks).
TEST(LiveSystemTest, MappingGrowsTheMapAlongTheDriveAsTheMappersOwn) {
  const ShortDrive& d = LiveDrive();
  LiveOptions options = Options();
  options.wait_for_perception = true;
  LiveSystem live(nullptr, options, d.truth.front().T_map_vehicle);
  EXPECT_TRUE(live.mapping());
  mapping::MapperOptions mapper_options;
  mapper_options.mode = mapping::MappingMode::kOnline;
  mapping::Mapper mapper(mapper_options, options.odometry, d.truth.front().T_map_vehicle);
  SensorLogSource source(d.simulation.log);
  size_t halfway_slots = 0;
  const TimeNs halfway_ns = (d.truth.front().t_ns + d.truth.back().t_ns) / 2;
  while (const auto event = source.Next()) {
    live.Process(*event);
    mapper.Process(*event);
    if (halfway_slots == 0 && EventTime(*event) >= halfway_ns) {
      halfway_slots = live.Map().slots.size();
    }
  }
  const std::optional<TimedPose> predicted = live.PredictedPose();
  ASSERT_TRUE(predicted.has_value());
  EXPECT_EQ(predicted->t_ns, mapper.current_time_ns());
  EXPECT_LT((predicted->T_map_vehicle.translation() - mapper.CurrentPose().translation()).norm(),
            1e-9);
  live.Finish();
  mapper.Finish();
  const size_t final_slots = live.Map().slots.size();
  EXPECT_GE(halfway_slots, 1u);
  EXPECT_GE(final_slots, halfway_slots + 5);
  EXPECT_EQ(final_slots, mapper.Map().slots.size());
  EXPECT_TRUE(live.TakeEstimates().empty());
  const Trajectory keyframes = live.KeyframeTrajectory();
  ASSERT_EQ(keyframes.size(), mapper.KeyframeTrajectory().size());
  EXPECT_EQ(keyframes.back().t_ns, mapper.KeyframeTrajectory().back().t_ns);
}

}  // namespace
}  // namespace parkslam::live
