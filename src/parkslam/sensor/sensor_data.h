#ifndef PARKSLAM_SENSOR_SENSOR_DATA_H_
#define PARKSLAM_SENSOR_SENSOR_DATA_H_

// Timestamped sensor structs: the one currency between data sources (the
// simulator, a recorded dataset, later a live vehicle) and everything
// downstream. Units and frames are in the field names (DESIGN.md 3).

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "parkslam/common/time.h"

namespace parkslam {

// Rear-wheel speed of the vehicle, signed (negative when reversing).
struct WheelSpeed {
  TimeNs t_ns = 0;
  double speed_mps = 0.0;
};

// Steering-wheel angle, positive to the left. The road-wheel angle is
// steering_wheel_rad / steering_ratio (VehicleParameters).
struct SteeringAngle {
  TimeNs t_ns = 0;
  double steering_wheel_rad = 0.0;
};

// A cheap IMU: gyroscope yaw rate and the AHRS heading (paper III-C, "the
// heading direction collected by IMU"), both in the map frame convention
// (counter-clockwise positive). Both carry biases that drift, and indoors
// the heading is disturbed near steel. Many cars have no compass at all: a
// gyro-only IMU gives no heading.
struct ImuSample {
  TimeNs t_ns = 0;
  double yaw_rate_radps = 0.0;
  std::optional<double> heading_rad;  // absent: no compass
};

// One hypothesis for one painted digit.
struct DigitHypothesis {
  char digit = '0';
  double probability = 0.0;
};

// The reader's output for one digit position: hypotheses sorted by falling
// probability. Empty when the digit could not be read at all.
struct DigitReading {
  std::vector<DigitHypothesis> hypotheses;
  bool read() const { return !hypotheses.empty(); }
};

// A slot-ID reading (paper III-A): digit by digit, with confidence. Empty
// `digits` means nothing was read; a reading with some unread digits is a
// partial ID.
struct SlotIdReading {
  std::vector<DigitReading> digits;

  bool empty() const { return digits.empty(); }
  // True when some but not all digits were read.
  bool partial() const;
  // The most likely ID, with '?' for unread digits ("3?"); "" when empty.
  std::string best() const;
  // Product of the top probabilities of the read digits; 0 when empty.
  double confidence() const;
};

// Corner order of a slot everywhere in the project: 0 and 1 are the ends of
// the entrance line (the side open to the aisle), 2 is behind 1 and 3 behind
// 0, so 0-1-2-3 walks round the slot counter-clockwise: walking from corner
// 0 to corner 1 along the entrance, the slot lies on the left.
inline constexpr int kSlotCorners = 4;

// One detected parking slot in the top view, in the vehicle frame.
struct SlotObservation {
  std::array<Eigen::Vector2d, kSlotCorners> corners_vehicle{};
  // True for corners really seen; false for corners guessed from the
  // standard slot depth (paper III-A: "the parking slot can only be guessed").
  std::array<bool, kSlotCorners> corner_observed{true, true, false, false};
  // Standard deviation of each observed corner coordinate, metres.
  double corner_sigma_m = 0.05;
  // Detector confidence that this is a slot at all, in [0, 1].
  double detection_confidence = 1.0;
  SlotIdReading id;
};

// All slots detected in one top-view frame.
struct SlotObservationFrame {
  TimeNs t_ns = 0;
  std::vector<SlotObservation> slots;
};

// One AprilTag seen by the front camera (paper III-B). The tag centre is
// at range_m and bearing_rad from the camera (bearing counter-clockwise from
// the camera's optical axis, projected on the ground plane); p_vehicle is
// the same point in the vehicle frame. yaw_vehicle_rad is the direction of
// the tag's outward normal in the vehicle frame (from PnP).
struct TagObservation {
  int tag_id = 0;
  Eigen::Vector2d p_vehicle = Eigen::Vector2d::Zero();
  double range_m = 0.0;
  double bearing_rad = 0.0;
  double yaw_vehicle_rad = 0.0;
  // Covariance of p_vehicle, square metres.
  Eigen::Matrix2d covariance_vehicle = Eigen::Matrix2d::Identity();
  // Standard deviation of yaw_vehicle_rad.
  double yaw_sigma_rad = 0.1;
};

struct TagObservationFrame {
  TimeNs t_ns = 0;
  std::vector<TagObservation> tags;
};

// An 8-bit grey image, row-major, without padding. Shared, so that
// events stay cheap to copy.
struct ImagePlane {
  int width = 0, height = 0;
  std::shared_ptr<const std::vector<std::uint8_t>> pixels;
};

// The images of one frame set of the rig's cameras, taken together.
struct CameraFrame {
  TimeNs t_ns = 0;
  std::vector<std::string> cameras;
  std::vector<ImagePlane> images;  // one per camera, same order
};

// One element of the sensor stream.
using SensorEvent = std::variant<WheelSpeed, SteeringAngle, ImuSample, SlotObservationFrame,
                                 TagObservationFrame, CameraFrame>;

inline TimeNs EventTime(const SensorEvent& event) {
  return std::visit([](const auto& e) { return e.t_ns; }, event);
}

}  // namespace parkslam

#endif  // PARKSLAM_SENSOR_SENSOR_DATA_H_
