#include "parkslam/mapping/mapper.h"

#include <gtest/gtest.h>

#include <functional>
#include <optional>

#include "parkslam/common/angles.h"

namespace parkslam::mapping {
namespace {

constexpr TimeNs kMs = 1'000'000;

struct TestSlot {
  std::array<Eigen::Vector2d, 4> corners_map;
};

// A perpendicular slot whose entrance runs along y = 3 from x to x + 2.5,
// the slot extending to +y (counter-clockwise corners).
TestSlot SlotAt(double x) {
  return {{Eigen::Vector2d(x, 3.0), Eigen::Vector2d(x + 2.5, 3.0), Eigen::Vector2d(x + 2.5, 8.3),
           Eigen::Vector2d(x, 8.3)}};
}

SlotIdReading Reading(const std::string& id, double p = 0.9) {
  SlotIdReading r;
  for (char c : id) r.digits.push_back(DigitReading{{{c, p}}});
  return r;
}

// Which ID the detector reads for slot `s` in frame `f`.
using ReadingFn = std::function<SlotIdReading(int s, int f)>;

// A straight drive along +x at 1 m/s from x = x0 to x1 (perfect odometry),
// the top view seeing slots whose entrance corners are within 5 m of the car.
// With tag_map, the front camera sees tag 7 there in every frame, facing -y,
// in a tag frame of the slot frame's time (as one camera frame set gives).
void Drive(Mapper& mapper, const std::vector<TestSlot>& slots, const ReadingFn& reading, double x0,
           double x1, double y = 0.0, TimeNs t0 = 0, int frame0 = 0,
           std::optional<Eigen::Vector2d> tag_map = std::nullopt) {
  const double speed = 1.0;
  const int steps = static_cast<int>((x1 - x0) / speed * 100);
  for (int i = 0; i <= steps; ++i) {
    const TimeNs t = t0 + i * 10 * kMs;
    const double x = x0 + speed * i * 0.01;
    mapper.Process(ImuSample{t, 0.0, 0.0});
    if (i % 2 == 0) {
      mapper.Process(WheelSpeed{t, speed});
      mapper.Process(SteeringAngle{t, 0.0});
    }
    if (i % 10 == 5) {
      SlotObservationFrame frame;
      frame.t_ns = t;
      const int f = frame0 + i / 10;
      for (int s = 0; s < static_cast<int>(slots.size()); ++s) {
        SlotObservation obs;
        bool visible = true;
        for (int j = 0; j < 4; ++j) {
          obs.corners_vehicle[j] = slots[s].corners_map[j] - Eigen::Vector2d(x, y);
          if (j < 2 && (std::abs(obs.corners_vehicle[j].x()) > 5 ||
                        std::abs(obs.corners_vehicle[j].y()) > 5)) {
            visible = false;
          }
        }
        if (!visible) continue;
        obs.corner_sigma_m = 0.03;
        obs.id = reading(s, f);
        frame.slots.push_back(obs);
      }
      mapper.Process(frame);
      if (tag_map) {
        TagObservation tag;
        tag.tag_id = 7;
        tag.p_vehicle = *tag_map - Eigen::Vector2d(x, y);
        tag.range_m = tag.p_vehicle.norm();
        tag.yaw_vehicle_rad = -kPi / 2;
        tag.covariance_vehicle = Eigen::Matrix2d::Identity() * 0.02 * 0.02;
        tag.yaw_sigma_rad = 0.05;
        mapper.Process(TagObservationFrame{t, {tag}});
      }
    }
  }
}

MapperOptions Options(RobustMode robust, MappingMode mode = MappingMode::kBatch) {
  MapperOptions o;
  o.robust = robust;
  o.mode = mode;
  return o;
}

const MapSlot* FindNear(const SemanticMap& map, const Eigen::Vector2d& corner0) {
  for (const MapSlot& s : map.slots) {
    if ((s.corners_map[0] - corner0).norm() < 0.5) return &s;
  }
  return nullptr;
}

TEST(MapperTest, TwoSlotsWithCorrectIdsAreMappedOnce) {
  Mapper mapper(Options(RobustMode::kMaxMixture), {}, SE2());
  const std::vector<TestSlot> slots{SlotAt(5.0), SlotAt(7.5)};
  Drive(
      mapper, slots, [](int s, int) { return Reading(s == 0 ? "38" : "39"); }, 0, 15);
  mapper.Finish();
  const SemanticMap map = mapper.Map();
  ASSERT_EQ(map.slots.size(), 2u);
  const MapSlot* a = FindNear(map, slots[0].corners_map[0]);
  ASSERT_NE(a, nullptr);
  EXPECT_EQ(a->id, "38");
  EXPECT_FALSE(a->temporary);
  EXPECT_LT((a->corners_map[2] - slots[0].corners_map[2]).norm(), 0.05);
  EXPECT_EQ(FindNear(map, slots[1].corners_map[0])->id, "39");
  // Where the drive began (its first keyframe, at the first frame 5 cm on).
  ASSERT_TRUE(map.entrance.has_value());
  EXPECT_LT((map.entrance->translation() - Eigen::Vector2d(0.05, 0.0)).norm(), 0.02);
  EXPECT_LT(std::abs(map.entrance->yaw()), 1e-3);
}

TEST(MapperTest, FirstReadingWrongThenCorrected) {
  // The paper's case: slot 39 read as 38 when first identified.
  Mapper mapper(Options(RobustMode::kMaxMixture), {}, SE2());
  const std::vector<TestSlot> slots{SlotAt(5.0)};
  Drive(
      mapper, slots, [](int, int f) { return Reading(f < 3 ? "38" : "39"); }, 0, 12);
  mapper.Finish();
  const SemanticMap map = mapper.Map();
  ASSERT_EQ(map.slots.size(), 1u);
  EXPECT_EQ(map.slots[0].id, "39");
}

TEST(MapperTest, TemporaryIdPromotedOnceReadingsAgree) {
  Mapper mapper(Options(RobustMode::kMaxMixture), {}, SE2());
  const std::vector<TestSlot> slots{SlotAt(5.0)};
  // Unreadable when first seen, then read from frame 60 on.
  Drive(
      mapper, slots, [](int, int f) { return f < 60 ? SlotIdReading{} : Reading("12"); }, 0, 12);
  mapper.Finish();
  ASSERT_EQ(mapper.Map().slots.size(), 1u);
  EXPECT_EQ(mapper.Map().slots[0].id, "12");
  EXPECT_FALSE(mapper.Map().slots[0].temporary);
}

TEST(MapperTest, NeverReadSlotKeepsTemporaryId) {
  Mapper mapper(Options(RobustMode::kMaxMixture), {}, SE2());
  Drive(
      mapper, {SlotAt(5.0)}, [](int, int) { return SlotIdReading{}; }, 0, 12);
  mapper.Finish();
  ASSERT_EQ(mapper.Map().slots.size(), 1u);
  EXPECT_TRUE(mapper.Map().slots[0].temporary);
  EXPECT_EQ(mapper.Map().slots[0].id.front(), 't');
}

TEST(MapperTest, PartialReadingsAssociateByGeometry) {
  Mapper mapper(Options(RobustMode::kMaxMixture), {}, SE2());
  Drive(
      mapper, {SlotAt(5.0)},
      [](int, int f) {
        SlotIdReading r = Reading("45");
        if (f % 3 == 1) r.digits[0] = DigitReading{};  // "?5"
        return r;
      },
      0, 12);
  mapper.Finish();
  ASSERT_EQ(mapper.Map().slots.size(), 1u);
  EXPECT_EQ(mapper.Map().slots[0].id, "45");
}

// Slot A (ID 38) seen first; then slot B, 5 m further (two slots between), read confidently
// as "38" as well. The Max-Mixture keeps them apart; the plain front-end
// trusts the ID and drags A towards B.
std::vector<TestSlot> FarPair() { return {SlotAt(5.0), SlotAt(10.0)}; }
SlotIdReading Misread(int, int) { return Reading("38"); }

TEST(MapperTest, MaxMixtureRejectsConfidentWrongIdFarAway) {
  Mapper mapper(Options(RobustMode::kMaxMixture), {}, SE2());
  Drive(mapper, FarPair(), Misread, 0, 18);
  mapper.Finish();
  const SemanticMap map = mapper.Map();
  ASSERT_EQ(map.slots.size(), 2u);
  const MapSlot* a = FindNear(map, FarPair()[0].corners_map[0]);
  const MapSlot* b = FindNear(map, FarPair()[1].corners_map[0]);
  ASSERT_NE(a, nullptr);
  ASSERT_NE(b, nullptr);
  // One of them carries the ID, the other a temporary one: IDs are unique.
  EXPECT_NE(a->temporary, b->temporary);
}

TEST(MapperTest, EverySlotKeepsAnObservationWhenOthersPickTheNull) {
  // B's later readings of "38" also name A; those picking the null must not
  // leave any slot without a factor: the founding observation stays tied.
  Mapper mapper(Options(RobustMode::kMaxMixture), {}, SE2());
  Drive(mapper, FarPair(), Misread, 0, 18);
  mapper.Finish();
  const auto& slots = mapper.slots();
  for (int s = 0; s < static_cast<int>(slots.size()); ++s) {
    if (!slots[s].alive) continue;
    EXPECT_GE(slots[s].observations, 1);
    // A record without a null component ties the slot for good.
    bool tied = false;
    for (const auto& record : mapper.slot_records()) {
      tied |= !record.has_null && record.candidates == std::vector<int>{s};
    }
    EXPECT_TRUE(tied) << "slot " << s;
  }
}

TEST(MapperTest, PlainFrontEndMergesSlotsOnConfidentWrongId) {
  Mapper mapper(Options(RobustMode::kNone), {}, SE2());
  Drive(mapper, FarPair(), Misread, 0, 18);
  mapper.Finish();
  // B's observations went to A: one slot, somewhere between the two.
  const SemanticMap map = mapper.Map();
  ASSERT_EQ(map.slots.size(), 1u);
  EXPECT_EQ(FindNear(map, FarPair()[1].corners_map[0]), nullptr);
}

TEST(MapperTest, DuplicatesFromEagerCreationAreMerged) {
  MapperOptions o = Options(RobustMode::kMaxMixture);
  o.null_chi2 = 1e-3;  // every observation wins as a new slot at first
  o.null_weight = 1.0;
  Mapper mapper(o, {}, SE2());
  Drive(
      mapper, {SlotAt(5.0)}, [](int, int) { return Reading("21"); }, 0, 12);
  mapper.Finish();
  EXPECT_GT(mapper.stats().slots_created, 5);
  EXPECT_GT(mapper.stats().slots_merged, 5);
  ASSERT_EQ(mapper.Map().slots.size(), 1u);
  EXPECT_EQ(mapper.Map().slots[0].id, "21");
}

TEST(MapperTest, SpuriousSingleDetectionIsDropped) {
  Mapper mapper(Options(RobustMode::kMaxMixture), {}, SE2());
  const std::vector<TestSlot> slots{SlotAt(5.0)};
  // Frame 40 also sees a false slot far off the row.
  Drive(
      mapper, slots, [](int, int) { return Reading("21"); }, 0, 12);
  SlotObservationFrame frame;
  frame.t_ns = 13'000 * kMs;
  SlotObservation ghost;
  ghost.corners_vehicle = {Eigen::Vector2d(1, -3), Eigen::Vector2d(3.5, -3),
                           Eigen::Vector2d(3.5, -8.3), Eigen::Vector2d(1, -8.3)};
  frame.slots.push_back(ghost);
  mapper.Process(ImuSample{frame.t_ns, 0, 0});
  mapper.Process(frame);
  mapper.Finish();
  EXPECT_EQ(mapper.Map().slots.size(), 1u);
}

TEST(MapperTest, TagSeenWithSlotsInOneFrameSetIsMapped) {
  // The slot frame makes the keyframe; the tag frame of the same time joins
  // it instead of being dropped for not having moved.
  Mapper mapper(Options(RobustMode::kMaxMixture), {}, SE2());
  const std::vector<TestSlot> slots{SlotAt(3.0), SlotAt(5.5), SlotAt(8.0), SlotAt(10.5)};
  const Eigen::Vector2d tag_map(8.0, -4.0);
  Drive(
      mapper, slots, [](int s, int) { return Reading(std::to_string(40 + s)); }, 0, 12, 0.0, 0, 0,
      tag_map);
  mapper.Finish();
  // Every keyframe is a frame set with slots and the tag in view.
  EXPECT_GT(mapper.stats().keyframes, 50);
  EXPECT_EQ(mapper.stats().tag_observations, mapper.stats().keyframes);
  const SemanticMap map = mapper.Map();
  ASSERT_EQ(map.tags.size(), 1u);
  EXPECT_EQ(map.tags[0].tag_id, 7);
  EXPECT_LT((map.tags[0].p_map - tag_map).norm(), 0.02);
  EXPECT_EQ(map.slots.size(), 4u);
}

TEST(MapperTest, OnlineModeBuildsTheSameSlots) {
  Mapper mapper(Options(RobustMode::kMaxMixture, MappingMode::kOnline), {}, SE2());
  const std::vector<TestSlot> slots{SlotAt(5.0), SlotAt(7.5), SlotAt(10.0)};
  Drive(
      mapper, slots, [](int s, int) { return Reading(std::to_string(40 + s)); }, 0, 18);
  mapper.Finish();
  const SemanticMap map = mapper.Map();
  ASSERT_EQ(map.slots.size(), 3u);
  EXPECT_EQ(FindNear(map, slots[2].corners_map[0])->id, "42");
  EXPECT_EQ(mapper.stats().keyframe_update_ms.size(),
            static_cast<size_t>(mapper.stats().keyframes));
}

TEST(MapperTest, OnlineBackgroundSolveGivesTheSameMapOnEveryRun) {
  // The background solve is laid in at a fixed time of the drive
  // (background_wait), however fast its thread: two runs, one map.
  const std::vector<TestSlot> slots{SlotAt(5.0), SlotAt(7.5), SlotAt(10.0)};
  MapperOptions options = Options(RobustMode::kMaxMixture, MappingMode::kOnline);
  options.background_solve_every_s = 0.5;
  std::vector<SemanticMap> maps;
  for (int run = 0; run < 2; ++run) {
    Mapper mapper(options, {}, SE2());
    Drive(
        mapper, slots, [](int s, int) { return Reading(std::to_string(40 + s)); }, 0, 18);
    // Along the drive the slots already carry the IDs their votes give.
    const SemanticMap along = mapper.Map(2);
    ASSERT_EQ(along.slots.size(), 3u);
    EXPECT_EQ(FindNear(along, slots[1].corners_map[0])->id, "41");
    EXPECT_GE(mapper.stats().background_solves, 15);
    EXPECT_EQ(mapper.stats().background_solve_ms.size(),
              static_cast<size_t>(mapper.stats().background_solves));
    mapper.Finish();
    maps.push_back(mapper.Map());
  }
  ASSERT_EQ(maps[0].slots.size(), 3u);
  ASSERT_EQ(maps[1].slots.size(), 3u);
  for (size_t s = 0; s < 3; ++s) {
    for (int j = 0; j < 4; ++j) {
      EXPECT_EQ(maps[0].slots[s].corners_map[j], maps[1].slots[s].corners_map[j]);
    }
  }
}

TEST(MapperTest, OnlineWithoutWaitingStillLaysInEveryFinishedSolve) {
  // A live car never waits: each solve is laid in once it has finished.
  const std::vector<TestSlot> slots{SlotAt(5.0), SlotAt(7.5)};
  MapperOptions options = Options(RobustMode::kMaxMixture, MappingMode::kOnline);
  options.background_wait = false;
  Mapper mapper(options, {}, SE2());
  Drive(
      mapper, slots, [](int s, int) { return Reading(s == 0 ? "38" : "39"); }, 0, 15);
  mapper.Finish();
  EXPECT_GE(mapper.stats().background_solves, 1);
  const SemanticMap map = mapper.Map();
  ASSERT_EQ(map.slots.size(), 2u);
  EXPECT_LT(
      (FindNear(map, slots[0].corners_map[0])->corners_map[2] - slots[0].corners_map[2]).norm(),
      0.05);
}

TEST(MapperTest, MalformedSlotObservationIsRejected) {
  Mapper mapper(Options(RobustMode::kMaxMixture), {}, SE2());
  // Clockwise corners: the slot would lie right of its entrance.
  TestSlot mirrored = SlotAt(5.0);
  std::swap(mirrored.corners_map[0], mirrored.corners_map[1]);
  std::swap(mirrored.corners_map[2], mirrored.corners_map[3]);
  Drive(
      mapper, {mirrored}, [](int, int) { return Reading("21"); }, 0, 12);
  mapper.Finish();
  EXPECT_TRUE(mapper.Map().slots.empty());
  EXPECT_GT(mapper.stats().rejected_slot_observations, 0);
}

TEST(MapperTest, InvalidOptionsThrow) {
  MapperOptions o;
  o.null_weight = 0.0;
  EXPECT_THROW(Mapper(o, {}, SE2()), std::invalid_argument);
  // A first trust region Ceres would refuse (it once left the map unsolved
  // and the command exited 0).
  for (const double radius : {1e300, 1e-40}) {
    MapperOptions t;
    t.initial_trust_region_radius = radius;
    std::string error;
    EXPECT_FALSE(t.IsValid(&error));
    EXPECT_EQ(error, "initial_trust_region_radius: must be in [1e-32, 1e+16]");
  }
  for (const double every_s : {-1.0, 1e300}) {
    MapperOptions b;
    b.background_solve_every_s = every_s;
    std::string error;
    EXPECT_FALSE(b.IsValid(&error));
    EXPECT_EQ(error.rfind("background_solve_every_s: ", 0), 0u) << error;
  }
  MapperOptions windowed_only;
  windowed_only.background_solve_every_s = 0.0;
  EXPECT_TRUE(windowed_only.IsValid(nullptr));
}

}  // namespace
}  // namespace parkslam::mapping
