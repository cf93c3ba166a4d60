#ifndef PARKSLAM_SIM_SENSOR_MODELS_H_
#define PARKSLAM_SIM_SENSOR_MODELS_H_

#include <cstdint>
#include <string>
#include <vector>

#include "parkslam/common/random.h"
#include "parkslam/sensor/sensor_data.h"
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
SlotIdReading SimulateIdReading(const std::string& painted_id,
                                const IdSensorConfig& config, Random& rng,
                                IdReadingOutcome* outcome = nullptr);

// Wheel speed, steering angle and IMU samples along the true drive.
void SimulateOdometrySensors(const std::vector<VehicleState>& states,
                             const OdometrySensorConfig& config,
                             const VehicleParameters& vehicle, std::uint64_t seed,
                             SensorLog* log);

// Slot detections from the top view at the true pose `state`, with the
// world slot index of each (-1 for a false detection) in *labels.
SlotObservationFrame SimulateSlotFrame(const World& world, const SE2& T_map_vehicle,
                                       TimeNs t_ns, const SensorConfig& config,
                                       Random& rng, std::vector<int>* labels);

// AprilTag detections of the front camera at the true pose.
TagObservationFrame SimulateTagFrame(const World& world, const SE2& T_map_vehicle,
                                     TimeNs t_ns, const TagSensorConfig& config,
                                     Random& rng);

}  // namespace parkslam::sim

#endif  // PARKSLAM_SIM_SENSOR_MODELS_H_
