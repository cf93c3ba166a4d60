#ifndef PARKSLAM_SIM_SIMULATOR_H_
#define PARKSLAM_SIM_SIMULATOR_H_

#include <cstdint>
#include <vector>

#include "parkslam/common/trajectory.h"
#include "parkslam/sensor/sensor_log.h"
#include "parkslam/sim/scenario_config.h"
#include "parkslam/sim/world.h"

namespace parkslam::sim {

// Which world slot each slot observation came from: one vector per slot
// frame, one entry per observation, an index into World::slots (and into the
// ground-truth map's slots, which keep the same order), or -1 for a false
// detection. Ground truth: for evaluation only, never for estimation.
using SlotObservationLabels = std::vector<std::vector<int>>;

// The ground-truth state of the vehicle at one instant.
struct VehicleState {
  TimeNs t_ns = 0;
  SE2 T_map_vehicle;
  double speed_mps = 0.0;
  double road_wheel_angle_rad = 0.0;
  double yaw_rate_radps = 0.0;
};

struct Simulation {
  World world;
  std::vector<VehicleState> states;  // ground truth at route.sample_rate_hz
  SensorLog log;
  SlotObservationLabels slot_labels;
};

// Runs the whole simulation at observation level: world (from
// config.world.seed, the same lot for every drive), human drive and sensors
// (from `seed`). Deterministic. Throws std::invalid_argument on an invalid
// configuration (the message names the field).
Simulation Simulate(const ScenarioConfig& config, std::uint64_t seed);

// The ground-truth trajectory of a simulation.
Trajectory GroundTruthTrajectory(const Simulation& simulation);

}  // namespace parkslam::sim

#endif  // PARKSLAM_SIM_SIMULATOR_H_
