#include "parkslam/harness/fault_injection.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <vector>

namespace parkslam::harness {
namespace {

using ::testing::HasSubstr;

constexpr TimeNs kMs = 1'000'000;

// 10 s of wheel speed and IMU at 100 Hz and camera frames (left and right,
// 2 x 2 images of value 7 + frame index) with slot frames at 10 Hz.
SensorLog Log() {
  SensorLog log;
  for (TimeNs t = 0; t < 10'000 * kMs; t += 10 * kMs) {
    log.wheel_speeds.push_back({t, 2.0});
    log.imu_samples.push_back({t, 0.1, 0.5});
  }
  for (TimeNs t = 0; t < 10'000 * kMs; t += 100 * kMs) log.slot_frames.push_back({t + 5 * kMs, {}});
  return log;
}

std::vector<SensorEvent> Drain(SensorSource& source) {
  std::vector<SensorEvent> events;
  while (auto e = source.Next()) events.push_back(*e);
  return events;
}

// A source of the log's events and a camera frame before each slot frame.
class WithCameras final : public SensorSource {
 public:
  explicit WithCameras(const SensorLog& log) : log_(log), inner_(log_) {}
  std::optional<SensorEvent> Next() override {
    if (pending_) {
      auto e = std::move(pending_);
      pending_.reset();
      return e;
    }
    auto e = inner_.Next();
    if (e && std::holds_alternative<SlotObservationFrame>(*e)) {
      CameraFrame frame;
      frame.t_ns = EventTime(*e);
      for (const char* name : {"left", "right"}) {
        frame.cameras.push_back(name);
        frame.images.push_back({2, 2,
                                std::make_shared<const std::vector<std::uint8_t>>(
                                    4, static_cast<std::uint8_t>(7 + count_))});
      }
      ++count_;
      pending_ = std::move(e);
      return frame;
    }
    return e;
  }

 private:
  SensorLog log_;
  SensorLogSource inner_;
  std::optional<SensorEvent> pending_;
  int count_ = 0;
};

template <typename T>
int Count(const std::vector<SensorEvent>& events, TimeNs from, TimeNs to) {
  int n = 0;
  for (const SensorEvent& e : events) {
    n += std::holds_alternative<T>(e) && EventTime(e) >= from && EventTime(e) < to;
  }
  return n;
}

TEST(FaultInjectionTest, ParsesFaultsAndNamesWhatIsWrong) {
  const SensorFault f = ParseSensorFault("camera-black@60+20,camera=rear");
  EXPECT_EQ(f.kind, FaultKind::kCameraBlack);
  EXPECT_EQ(f.start_s, 60.0);
  EXPECT_EQ(f.duration_s, 20.0);
  EXPECT_EQ(f.camera, "rear");
  EXPECT_EQ(ParseSensorFault("heading-jump@1+2").magnitude, 0.5);
  EXPECT_EQ(ParseSensorFault("clock-jitter@1+2,magnitude=0.05").magnitude, 0.05);
  const auto error = [](const std::string& text) {
    try {
      ParseSensorFault(text);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_THAT(error("camera-blak@1+2"), HasSubstr("unknown kind 'camera-blak'"));
  EXPECT_THAT(error("imu-spikes@x+2"), HasSubstr("START: not a number: 'x'"));
  EXPECT_THAT(error("imu-spikes@1"), HasSubstr("START+DURATION"));
  EXPECT_THAT(error("imu-spikes@1+0"), HasSubstr("DURATION > 0"));
  EXPECT_THAT(error("imu-spikes@1+2,speed=3"), HasSubstr("unknown option 'speed=3'"));
  EXPECT_THAT(error("imu-spikes@1+2,magnitude=nan"), HasSubstr("not a number"));
}

TEST(FaultInjectionTest, CameraGapAndWheelDropoutRemoveTheirEventsInTheWindowOnly) {
  const SensorLog log = Log();
  WithCameras cameras(log);
  FaultInjectingSource source(
      cameras, {ParseSensorFault("camera-gap@2+3"), ParseSensorFault("wheel-dropout@6+1")}, 1);
  const std::vector<SensorEvent> events = Drain(source);
  EXPECT_EQ(Count<SlotObservationFrame>(events, 2000 * kMs, 5000 * kMs), 0);
  EXPECT_EQ(Count<CameraFrame>(events, 2000 * kMs, 5000 * kMs), 0);
  EXPECT_EQ(Count<SlotObservationFrame>(events, 5000 * kMs, 6000 * kMs), 10);
  EXPECT_EQ(Count<WheelSpeed>(events, 6000 * kMs, 7000 * kMs), 0);
  EXPECT_EQ(Count<WheelSpeed>(events, 5000 * kMs, 6000 * kMs), 100);
  EXPECT_EQ(Count<ImuSample>(events, 6000 * kMs, 7000 * kMs), 100);
  EXPECT_EQ(source.injected().frames_dropped, 60);
  EXPECT_EQ(source.injected().wheel_samples_dropped, 100);
}

TEST(FaultInjectionTest, BlackAndFrozenCamerasChangeOnlyThatCamera) {
  const SensorLog log = Log();
  WithCameras cameras(log);
  FaultInjectingSource source(cameras,
                              {ParseSensorFault("camera-black@2+1,camera=left"),
                               ParseSensorFault("camera-frozen@5+1,camera=right")},
                              1);
  for (const SensorEvent& e : Drain(source)) {
    const auto* frame = std::get_if<CameraFrame>(&e);
    if (frame == nullptr) continue;
    const int index = static_cast<int>((frame->t_ns - 5 * kMs) / (100 * kMs));
    const std::uint8_t left = (*frame->images[0].pixels)[0];
    const std::uint8_t right = (*frame->images[1].pixels)[0];
    const bool black = index >= 20 && index < 30, frozen = index >= 50 && index < 60;
    EXPECT_EQ(left, black ? 0 : 7 + index) << index;
    EXPECT_EQ(right, frozen ? 7 + 49 : 7 + index) << index;
  }
  EXPECT_EQ(source.injected().images_blackened, 10);
  EXPECT_EQ(source.injected().images_frozen, 10);
}

TEST(FaultInjectionTest, LateFramesArriveAfterLaterEvents) {
  const SensorLog log = Log();
  SensorLogSource inner(log);
  FaultInjectingSource source(inner, {ParseSensorFault("late-frames@2+1,magnitude=0.3")}, 1);
  const std::vector<SensorEvent> events = Drain(source);
  EXPECT_EQ(events.size(),
            log.wheel_speeds.size() + log.imu_samples.size() + log.slot_frames.size());
  int out_of_order = 0;
  TimeNs latest = 0;
  for (const SensorEvent& e : events) {
    if (EventTime(e) < latest) {
      ++out_of_order;
      EXPECT_TRUE(std::holds_alternative<SlotObservationFrame>(e));
      EXPECT_NEAR(static_cast<double>(latest - EventTime(e)), 300.0 * kMs, 10.0 * kMs);
    }
    latest = std::max(latest, EventTime(e));
  }
  EXPECT_EQ(out_of_order, 10);
  EXPECT_EQ(source.injected().frames_delayed, 10);
}

TEST(FaultInjectionTest, ImuSpikesHeadingJumpAndJitterAreSeededAndBounded) {
  const SensorLog log = Log();
  const auto run = [&log](std::uint64_t seed) {
    SensorLogSource inner(log);
    FaultInjectingSource source(
        inner,
        {ParseSensorFault("imu-spikes@1+2"), ParseSensorFault("heading-jump@4+1"),
         ParseSensorFault("clock-jitter@6+1,magnitude=0.01")},
        seed);
    std::vector<SensorEvent> events = Drain(source);
    EXPECT_EQ(source.injected().imu_spikes, 4);
    EXPECT_EQ(source.injected().heading_samples_shifted, 100);
    EXPECT_EQ(source.injected().events_jittered, 210);  // wheel, IMU, slot frames
    return events;
  };
  const std::vector<SensorEvent> a = run(1), b = run(1), c = run(2);
  int spikes = 0, shifted = 0, jittered = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(EventTime(a[k]), EventTime(b[k]));
    if (const auto* imu = std::get_if<ImuSample>(&a[k])) {
      spikes += std::abs(std::abs(imu->yaw_rate_radps - 0.1) - 2.0) < 1e-9;
      shifted += std::abs(*imu->heading_rad - 1.0) < 1e-9;
    }
    jittered += EventTime(a[k]) != EventTime(c[k]);
  }
  EXPECT_EQ(spikes, 4);
  EXPECT_EQ(shifted, 100);
  EXPECT_GT(jittered, 150);  // two seeds, two different jitters
}

}  // namespace
}  // namespace parkslam::harness
