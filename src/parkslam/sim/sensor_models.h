#ifndef PARKSLAM_SIM_SENSOR_MODELS_H_
#define PARKSLAM_SIM_SENSOR_MODELS_H_

#include <cstdint>
#include <string>
#include <vector>

#include "parkslam/common/random.h"
#include "parkslam/sensor/sensor_data.h"
#include "parkslam/sim/compass_field.h"
#include "parkslam/sim/scenario_config.h"
#include "parkslam/sim/simulator.h"
#include "parkslam/sim/world.h"

namespace parkslam::sim {

// Digits a reader tends to take for one another (3/8, 1/7, 5/6, 0/8 ...).
const std::string& ConfusableDigits(char digit);

// Outcome of one simulated ID reading, for tests of the error rates.
enum class IdReadingOutcome { kCorrect, kConfused, kPartial, kUnreadable };

// One reading of a legible painted ID under the configured error model
// (IdSensorConfig). Writes the outcome drawn when `outcome` is not null.
SlotIdReading SimulateIdReading(const std::string& painted_id, const IdSensorConfig& config,
                                Random& rng, IdReadingOutcome* outcome = nullptr);

// Tags of the random streams (Random::Derive(seed, tag)) that the sensor
// models draw from, one per sensor, shared by the batch simulator and the
// live one so that a seed gives both the same noise.
inline constexpr std::uint64_t kWheelStreamTag = 0x101;
inline constexpr std::uint64_t kSteeringStreamTag = 0x102;
inline constexpr std::uint64_t kImuStreamTag = 0x103;
inline constexpr std::uint64_t kSlotFrameStreamTag = 0x201;
inline constexpr std::uint64_t kTagFrameStreamTag = 0x202;

// Wheel speed, steering angle and IMU, one sample at a time, from the true
// state of the vehicle. Keeps the per-drive errors (wheel-speed scale, gyro
// and heading biases) and a separate random stream per sensor, so the
// samples of one sensor do not depend on how many another has taken.
//   wheel    = (1 + e_scale) v + n_v,         e_scale ~ N(0, wheel_speed_scale_sigma)
//   steering = steering_ratio delta + n_s
//   gyro     = yaw_rate + b_g + n_g,          b_g(0) ~ N(0, gyro_bias_sigma_radps)
//   heading  = yaw + b_h + n_h + d(p),        b_h(0) ~ N(0, heading_bias_sigma_rad)
// with b_g and b_h random walks advanced by MeasureImu, and d(p) the
// compass's disturbance where the car is (CompassField). Without a compass
// (CompassConfig::model "none") the samples carry no heading.
class OdometrySensorModel {
 public:
  OdometrySensorModel(const OdometrySensorConfig& config, const VehicleParameters& vehicle,
                      std::uint64_t seed, CompassField compass = {}, bool has_compass = true);

  WheelSpeed MeasureWheel(const VehicleState& true_state, TimeNs t_ns);
  SteeringAngle MeasureSteering(const VehicleState& true_state, TimeNs t_ns);
  // Measures with the current biases, then advances the bias random walks by
  // dt_s, the time to the next IMU sample.
  ImuSample MeasureImu(const VehicleState& true_state, TimeNs t_ns, double dt_s);

  const OdometrySensorConfig& config() const { return config_; }

 private:
  OdometrySensorConfig config_;
  VehicleParameters vehicle_;
  Random wheel_rng_, steering_rng_, imu_rng_;
  double wheel_speed_scale_ = 1.0;
  double gyro_bias_radps_ = 0.0;
  double heading_bias_rad_ = 0.0;
  CompassField compass_;
  bool has_compass_ = true;
};

// Wheel speed, steering angle and IMU samples along the true drive, each
// sensor at its rate from the first state on, measured at the nearest state.
// The first takes a compass that nothing disturbs.
void SimulateOdometrySensors(const std::vector<VehicleState>& states,
                             const OdometrySensorConfig& config, const VehicleParameters& vehicle,
                             std::uint64_t seed, SensorLog* log);
void SimulateOdometrySensors(const std::vector<VehicleState>& states, OdometrySensorModel model,
                             SensorLog* log);

// The odometry sensors of a scenario in its world: the compass as its
// sensors.compass says (disturbed, clean or none).
OdometrySensorModel MakeOdometrySensorModel(const SensorConfig& sensors,
                                            const VehicleParameters& vehicle, const World& world,
                                            std::uint64_t seed);

// Slot detections from the top view at the true pose `state`, with the
// world slot index of each (-1 for a false detection) in *labels.
SlotObservationFrame SimulateSlotFrame(const World& world, const SE2& T_map_vehicle, TimeNs t_ns,
                                       const SensorConfig& config, Random& rng,
                                       std::vector<int>* labels);

// AprilTag detections of the front camera at the true pose.
TagObservationFrame SimulateTagFrame(const World& world, const SE2& T_map_vehicle, TimeNs t_ns,
                                     const TagSensorConfig& config, Random& rng);

}  // namespace parkslam::sim

#endif  // PARKSLAM_SIM_SENSOR_MODELS_H_
