#ifndef PARKSLAM_HARNESS_FAULT_INJECTION_H_
#define PARKSLAM_HARNESS_FAULT_INJECTION_H_

// Sensor faults injected into a stream (docs/robustness.md, "Sensor
// faults"): the same faults for a simulated drive and for a recorded one,
// since both are a SensorSource. Each fault acts in a window of the
// stream's time, counted from its first event:
//
//   camera-gap     no camera frames, slot or tag frames at all
//   camera-black   one camera's images are black
//   camera-frozen  one camera repeats its last image from before the window
//   late-frames    camera, slot and tag frames arrive magnitude seconds late,
//                  after the events that follow them (out of order)
//   imu-spikes     every 0.5 s one IMU sample carries a yaw-rate spike of
//                  +-magnitude rad/s and a heading spike of -+magnitude/4 rad
//   heading-jump   the AHRS heading reads magnitude rad more
//   wheel-dropout  no wheel-speed samples
//   clock-jitter   every event's time moves by a normal error of magnitude
//                  seconds (so some arrive out of order)
//
// A fault is written KIND@START+DURATION[,camera=NAME][,magnitude=X], with
// START and DURATION in seconds: "camera-black@60+20,camera=left".

#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "parkslam/common/time.h"
#include "parkslam/sensor/sensor_log.h"

namespace parkslam::harness {

enum class FaultKind {
  kCameraGap,
  kCameraBlack,
  kCameraFrozen,
  kLateFrames,
  kImuSpikes,
  kHeadingJump,
  kWheelDropout,
  kClockJitter,
};
const char* ToString(FaultKind kind);

struct SensorFault {
  FaultKind kind = FaultKind::kCameraGap;
  double start_s = 0.0;  // after the stream's first event
  double duration_s = 0.0;
  std::string camera = "left";  // camera-black, camera-frozen
  // late-frames: the delay (s); imu-spikes: the spike (rad/s and rad);
  // heading-jump: the jump (rad); clock-jitter: the standard deviation (s).
  double magnitude = 0.0;

  // The fault's text form (above).
  std::string ToText() const;
};

// The fault of `magnitude` 0 takes its kind's default: late-frames 0.5 s,
// imu-spikes 2 rad/s and 0.5 rad, heading-jump 0.5 rad, clock-jitter
// 0.02 s.
double DefaultMagnitude(FaultKind kind);

// Parses KIND@START+DURATION[,camera=NAME][,magnitude=X]. Throws
// std::invalid_argument naming the part that is wrong.
SensorFault ParseSensorFault(const std::string& text);

// What the injector did.
struct InjectedFaults {
  int frames_dropped = 0;  // camera, slot and tag frames (camera-gap)
  int images_blackened = 0;
  int images_frozen = 0;
  int frames_delayed = 0;
  int imu_spikes = 0;
  int heading_samples_shifted = 0;
  int wheel_samples_dropped = 0;
  int events_jittered = 0;
};

// Passes `inner` through with the faults applied. inner must outlive it.
class FaultInjectingSource final : public SensorSource {
 public:
  FaultInjectingSource(SensorSource& inner, std::vector<SensorFault> faults, std::uint64_t seed);
  std::optional<SensorEvent> Next() override;

  const InjectedFaults& injected() const { return injected_; }
  // The fault windows in stream time (ns), once the first event was seen.
  TimeNs start_ns() const { return start_ns_.value_or(0); }

 private:
  bool Active(const SensorFault& fault, TimeNs t_ns) const;
  // Applies the faults to one event; false when it is dropped.
  bool Apply(SensorEvent* event);
  std::optional<SensorEvent> Pull();

  SensorSource& inner_;
  std::vector<SensorFault> faults_;
  std::mt19937_64 rng_;
  std::optional<TimeNs> start_ns_;
  std::optional<SensorEvent> lookahead_;
  // Delayed frames and the inner time from which they are released.
  std::vector<std::pair<TimeNs, SensorEvent>> delayed_;
  // Per fault: the last image of its camera before the window (frozen).
  std::vector<ImagePlane> last_image_;
  std::vector<TimeNs> next_spike_ns_;
  InjectedFaults injected_;
};

}  // namespace parkslam::harness

#endif  // PARKSLAM_HARNESS_FAULT_INJECTION_H_
