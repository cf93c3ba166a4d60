#include "parkslam/perception/front_end.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "parkslam/camera/image_plane.h"
#include "parkslam/common/angles.h"
#include "parkslam/harness/rendering_source.h"
#include "parkslam/render/renderer.h"
#include "parkslam/sim/simulator.h"

namespace parkslam::perception {
namespace {

using harness::RenderCameraFrame;
using harness::RenderingSource;

const std::vector<std::string> kCameras{"front", "rear", "left", "right", "front_mono"};

struct Lot {
  sim::ScenarioConfig scenario = sim::DefaultScenario();
  sim::World world = sim::BuildWorld(scenario.world);
};

const Lot& DefaultLot() {
  static const Lot lot;
  return lot;
}

const harness::FrameRenderer& Renderer() {
  static const harness::FrameRenderer r(DefaultLot().world, sim::WorldConfig{},
                                        camera::DefaultRig(), 11);
  return r;
}

// The classical front end (the learned one is the default, tested below).
const PerceptionFrontEnd& FrontEnd() {
  static const PerceptionFrontEnd f(camera::DefaultRig(), [] {
    PerceptionOptions options;
    options.detector = DetectorKind::kClassical;
    return options;
  }());
  return f;
}

// In aisle 1, heading east between rows A and B: every slot seen in the top
// view lies where the world says, with its painted ID.
TEST(PerceptionFrontEndTest, SlotsInTheAisleLandOnTheTruth) {
  const SE2 T_map_vehicle(30.0, 9.1, 0.0);
  const PerceptionOutput out =
      FrontEnd().Process(RenderCameraFrame(Renderer(), T_map_vehicle, 0, kCameras));
  ASSERT_GE(out.slots.slots.size(), 4u);
  const SE2 T_vehicle_map = T_map_vehicle.inverse();
  int with_id = 0;
  for (const SlotObservation& obs : out.slots.slots) {
    // The true slot whose entrance corners are nearest.
    double best = 1e9;
    const sim::WorldSlot* match = nullptr;
    for (const sim::WorldSlot& slot : DefaultLot().world.slots) {
      const double d = (T_vehicle_map * slot.corners_map[0] - obs.corners_vehicle[0]).norm() +
                       (T_vehicle_map * slot.corners_map[1] - obs.corners_vehicle[1]).norm();
      if (d < best) best = d, match = &slot;
    }
    ASSERT_NE(match, nullptr);
    EXPECT_LT(best, 0.06) << "entrance corners off by " << best << " m in sum";
    EXPECT_FALSE(obs.corner_observed[2] || obs.corner_observed[3]);
    if (!obs.id.empty() && !obs.id.partial()) {
      EXPECT_EQ(obs.id.best(), match->painted_id);
      ++with_id;
    }
  }
  EXPECT_GE(with_id, 2);
  EXPECT_GT(out.timing.total_ms(), 0.0);
}

// The learned front end (docs/learned_perception.md) in the same place:
// at least four slots, every one on a true slot with its entrance corners
// within 3 cm in sum (refined on the paint; the network's cells alone are
// 4 cm wide), and its ID right where read whole. Before the paint check,
// one slot of this frame was false (it paired corners of two slots across
// a missed one).
TEST(PerceptionFrontEndTest, LearnedSlotsInTheAisleLandOnTheTruth) {
  PerceptionOptions options;
  EXPECT_EQ(options.detector, DetectorKind::kLearned);  // the default
  options.detector = DetectorKind::kLearned;
  const PerceptionFrontEnd learned(camera::DefaultRig(), options);
  const SE2 T_map_vehicle(30.0, 9.1, 0.0);
  const PerceptionOutput out =
      learned.Process(RenderCameraFrame(Renderer(), T_map_vehicle, 0, kCameras));
  ASSERT_GE(out.slots.slots.size(), 4u);
  const SE2 T_vehicle_map = T_map_vehicle.inverse();
  int with_id = 0;
  for (const SlotObservation& obs : out.slots.slots) {
    double best = 1e9;
    const sim::WorldSlot* match = nullptr;
    for (const sim::WorldSlot& slot : DefaultLot().world.slots) {
      const double d = (T_vehicle_map * slot.corners_map[0] - obs.corners_vehicle[0]).norm() +
                       (T_vehicle_map * slot.corners_map[1] - obs.corners_vehicle[1]).norm();
      if (d < best) best = d, match = &slot;
    }
    ASSERT_NE(match, nullptr);
    EXPECT_LT(best, 0.03) << "entrance corners off by " << best << " m in sum";
    if (!obs.id.empty() && !obs.id.partial()) {
      EXPECT_EQ(obs.id.best(), match->painted_id);
      ++with_id;
    }
  }
  EXPECT_GE(with_id, 4);
}

// A top view fused elsewhere (here: by this front end's own fusion) in
// place of the fisheyes gives the very slots; a wrong size is refused.
TEST(PerceptionFrontEndTest, ATopViewGivenInPlaceOfTheFisheyesGivesTheSameSlots) {
  const PerceptionFrontEnd& front_end = FrontEnd();
  const CameraFrame fisheyes = RenderCameraFrame(Renderer(), SE2(30.0, 9.1, 0.0), 0, kCameras);
  const PerceptionOutput from_fisheyes = front_end.Process(fisheyes);
  ASSERT_GE(from_fisheyes.slots.slots.size(), 4u);
  CameraFrame given;
  given.t_ns = fisheyes.t_ns;
  given.cameras = {kTopViewCamera, "front_mono"};
  given.images = {camera::ToImagePlane(from_fisheyes.top_view), fisheyes.images.back()};
  ASSERT_EQ(fisheyes.cameras.back(), "front_mono");
  const PerceptionOutput from_top_view = front_end.Process(given);
  ASSERT_EQ(from_top_view.slots.slots.size(), from_fisheyes.slots.slots.size());
  for (size_t k = 0; k < from_top_view.slots.slots.size(); ++k) {
    for (int c = 0; c < kSlotCorners; ++c) {
      EXPECT_LT((from_top_view.slots.slots[k].corners_vehicle[c] -
                 from_fisheyes.slots.slots[k].corners_vehicle[c])
                    .norm(),
                1e-9);
    }
    EXPECT_EQ(from_top_view.slots.slots[k].id.best(), from_fisheyes.slots.slots[k].id.best());
  }
  EXPECT_EQ(from_top_view.tags.tags.size(), from_fisheyes.tags.tags.size());
  CameraFrame wrong = given;
  wrong.images[0] = camera::ToImagePlane(cv::Mat::zeros(300, 300, CV_8UC1));
  EXPECT_THROW(front_end.Process(wrong), std::invalid_argument);
}

// At the corridor's start the front camera sees tags: each lies where the
// world has it, and faces the way it does (the direct angle chose the PnP
// solution; the other one of a planar target flips the normal).
TEST(PerceptionFrontEndTest, TagsLandOnTheTruthAndFaceTheRightWay) {
  const Lot& lot = DefaultLot();
  int seen = 0;
  for (double x : {-37.0, -30.0, -20.0}) {
    const SE2 T_map_vehicle(x, 9.1, 0.0);
    const PerceptionOutput out =
        FrontEnd().Process(RenderCameraFrame(Renderer(), T_map_vehicle, 0, kCameras));
    for (const TagObservation& obs : out.tags.tags) {
      const sim::WorldTag* tag = nullptr;
      for (const sim::WorldTag& t : lot.world.tags) {
        if (t.tag_id == obs.tag_id) tag = &t;
      }
      ASSERT_NE(tag, nullptr) << "tag " << obs.tag_id << " is not in the world";
      const Eigen::Vector2d p_map = T_map_vehicle * obs.p_vehicle;
      const double range = obs.range_m;
      EXPECT_LT((p_map - tag->p_map).norm(), 0.05 + 0.02 * range) << "tag " << obs.tag_id;
      EXPECT_LT(std::abs(AngleDiff(obs.yaw_vehicle_rad + T_map_vehicle.yaw(), tag->normal_yaw_rad)),
                DegToRad(10.0))
          << "tag " << obs.tag_id << " at " << range << " m";
      EXPECT_GT(obs.covariance_vehicle.determinant(), 0.0);
      ++seen;
    }
  }
  EXPECT_GE(seen, 3);
}

// Looked for only where the map has them, from the true pose: the tags of
// the whole band, in the same place within a centimetre (a near tag is
// found on a coarser image), for a fraction of the band's search. A pose
// too uncertain for windows, or the option off, searches the band; from a
// place whose view holds no tag, nothing is searched.
TEST(PerceptionFrontEndTest, TagWindowsFindTheBandsTagsWhereTheMapHasThem) {
  const SemanticMap map = sim::ToSemanticMap(DefaultLot().world);
  const Eigen::Matrix3d P = Eigen::Vector3d(0.1, 0.1, 0.02).cwiseAbs2().asDiagonal();
  const camera::CameraRig rig = camera::DefaultRig();
  const auto mono = std::find_if(rig.cameras.begin(), rig.cameras.end(),
                                 [](const auto& c) { return c.name == camera::kTagCameraName; });
  ASSERT_NE(mono, rig.cameras.end());
  const camera::CameraIntrinsics& k = mono->intrinsics;
  int compared = 0, coarse = 0;
  for (double x : {-37.0, -30.0, -20.0}) {
    const SE2 T_map_vehicle(x, 9.1, 0.0);
    const CameraFrame frame = RenderCameraFrame(Renderer(), T_map_vehicle, 0, kCameras);
    PerceptionOutput band, windowed;
    FrontEnd().PerceiveTags(frame, {}, &band);
    const std::optional<std::vector<TagWindow>> windows =
        FrontEnd().TagWindows(map.tags, T_map_vehicle, P);
    ASSERT_TRUE(windows.has_value()) << x;
    FrontEnd().PerceiveTags(frame, {}, &windowed, &*windows);
    double cost = 0.0;
    for (const TagWindow& w : *windows) {
      cost += static_cast<double>(w.rect.area()) / (w.decimate * w.decimate);
      EXPECT_EQ(w.rect.x % 8, 0);
      EXPECT_EQ(w.rect.width % 8, 0);
      coarse += w.decimate > 2;
    }
    // Against the band's search at decimation 2 (a band under half the image).
    EXPECT_LT(cost, 0.5 * k.width * k.height / 2 / 4) << x;
    ASSERT_EQ(windowed.tags.tags.size(), band.tags.tags.size()) << x;
    for (const TagObservation& b : band.tags.tags) {
      const auto same = std::find_if(windowed.tags.tags.begin(), windowed.tags.tags.end(),
                                     [&](const TagObservation& w) { return w.tag_id == b.tag_id; });
      ASSERT_NE(same, windowed.tags.tags.end()) << "tag " << b.tag_id;
      EXPECT_LT((same->p_vehicle - b.p_vehicle).norm(), 0.01) << "tag " << b.tag_id;
      ++compared;
    }
  }
  EXPECT_GE(compared, 3);
  EXPECT_GE(coarse, 1);
  const SE2 near_tags(-30.0, 9.1, 0.0);
  EXPECT_FALSE(
      FrontEnd()
          .TagWindows(map.tags, near_tags, Eigen::Vector3d(3.0, 3.0, 0.5).cwiseAbs2().asDiagonal())
          .has_value());
  PerceptionOptions off;
  off.detector = DetectorKind::kClassical;
  off.tag_windows.enabled = false;
  EXPECT_FALSE(
      PerceptionFrontEnd(camera::DefaultRig(), off).TagWindows(map.tags, near_tags, P).has_value());
  // Far outside the lot, looking away from it.
  const std::optional<std::vector<TagWindow>> none =
      FrontEnd().TagWindows(map.tags, SE2(-500.0, 9.1, M_PI), P);
  ASSERT_TRUE(none.has_value());
  EXPECT_TRUE(none->empty());
}

// The stream on pixels: camera frames become slot and tag frames at their
// time; the simulator's own detections are dropped.
TEST(PerceptionSourceTest, ReplacesObservationsByWhatTheCamerasSee) {
  sim::ScenarioConfig scenario = sim::DefaultScenario();
  scenario.route.laps = 0;
  scenario.route.finish_m = {{-20.0, 9.1}};
  const sim::Simulation simulation = sim::Simulate(scenario, 4);
  const Trajectory truth = sim::GroundTruthTrajectory(simulation);
  SensorLogSource log(simulation.log);
  RenderingSource rendering(log, Renderer(), truth, kCameras, 1.0);
  PerceptionSource source(rendering, FrontEnd());
  int slot_frames = 0, tag_frames = 0, cameras = 0;
  TimeNs last = -1;
  while (const auto event = source.Next()) {
    ASSERT_GE(EventTime(*event), last);
    last = EventTime(*event);
    if (const auto* f = std::get_if<SlotObservationFrame>(&*event)) {
      EXPECT_EQ(f->t_ns % 1'000'000'000LL, truth.front().t_ns % 1'000'000'000LL);
      ++slot_frames;
    }
    tag_frames += std::holds_alternative<TagObservationFrame>(*event);
    cameras += std::holds_alternative<CameraFrame>(*event);
  }
  EXPECT_EQ(cameras, 0);
  EXPECT_EQ(slot_frames, source.frames_processed());
  EXPECT_EQ(tag_frames, source.frames_processed());
  EXPECT_EQ(source.frames_processed(), rendering.frames_rendered());
  EXPECT_GT(source.frames_processed(), 5);
}

TEST(PerceptionFrontEndTest, TheLearnedDetectorRefusesAnotherScale) {
  PerceptionOptions options;       // learned
  options.top_view.size_px = 500;  // 50 px a metre
  try {
    PerceptionFrontEnd f(camera::DefaultRig(), options);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("top_view: the learned detector needs 60 px a metre"),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("got 500 px for 10 m"), std::string::npos) << e.what();
  }
  options.detector = DetectorKind::kClassical;
  EXPECT_NO_THROW(PerceptionFrontEnd(camera::DefaultRig(), options));
}

TEST(PerceptionFrontEndTest, MissingCamerasAreNamed) {
  camera::CameraRig rig = camera::DefaultRig();
  rig.cameras.erase(rig.cameras.begin());  // "front"
  try {
    PerceptionFrontEnd f(rig);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'front'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace parkslam::perception
