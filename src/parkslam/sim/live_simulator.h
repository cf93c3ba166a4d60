#ifndef PARKSLAM_SIM_LIVE_SIMULATOR_H_
#define PARKSLAM_SIM_LIVE_SIMULATOR_H_

#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "parkslam/common/random.h"
#include "parkslam/common/se2.h"
#include "parkslam/common/time.h"
#include "parkslam/sensor/sensor_data.h"
#include "parkslam/sim/scenario_config.h"
#include "parkslam/sim/sensor_models.h"
#include "parkslam/sim/simulator.h"
#include "parkslam/sim/world.h"

namespace parkslam::sim {

// What lies between a controller's commands and the road on a real car
// (all zero: the ideal kinematic bicycle that obeys at once):
//   a command acts actuator_delay_s after it is given (the CAN bus, the
//     steering and brake controllers);
//   the speed follows the delayed command as a first-order lag of time
//     constant speed_lag_s (the speed controller), within the route's
//     acceleration limits; the road wheels turn at most at the vehicle's
//     max_road_wheel_rate_radps (as always);
//   in a turn, the tyres slip: the road-wheel angle that acts is smaller by
//     understeer_gradient_rad_per_mps2 per m/s^2 of lateral acceleration,
//     and the body moves sideslip_rad_per_mps2 per m/s^2 outwards of its
//     heading (the rear drifts out).
struct VehicleDynamics {
  double actuator_delay_s = 0.0;
  double speed_lag_s = 0.0;
  double understeer_gradient_rad_per_mps2 = 0.0;
  double sideslip_rad_per_mps2 = 0.0;

  bool IsValid(std::string* error) const;
};

// A passenger car's: 0.15 s delay, 0.5 s speed lag, understeer 0.004 rad
// and sideslip 0.005 rad per m/s^2 (about 0.2 and 0.3 degrees per m/s^2).
VehicleDynamics RealisticDynamics();

struct LiveSimulatorOptions {
  double step_hz = 100.0;  // rate of Step(); the bicycle integrates 1 / step_hz
  VehicleDynamics dynamics;

  bool IsValid(std::string* error) const;
};

// The simulator step by step, for closed loops: a controller commands speed
// and road-wheel angle, the kinematic bicycle (StepBicycle) moves the true
// car, and the sensors of the batch simulator (Simulate) observe the true
// pose as it evolves, at the same times as there: every sensor at its rate
// from t = 0, the tag frames half a tag period after the slot frames.
// Deterministic by seed. The noise streams are those of the batch simulator
// (the stream tags of sensor_models.h), so a seed gives both the same noise
// statistics; the live simulator draws nothing of its own.
class LiveSimulator {
 public:
  // The world is built from scenario.world with its own seed
  // (scenario.world.seed), the lot of the batch simulator; `seed` decides
  // the sensor noise. Sensors from scenario.sensors, vehicle from
  // scenario.vehicle; speed and steering start at zero, the time at 0.
  // Throws std::invalid_argument when the scenario or the options are
  // invalid (the message names the field).
  LiveSimulator(const ScenarioConfig& scenario, std::uint64_t seed, const SE2& T_map_vehicle_start,
                const LiveSimulatorOptions& options = {});

  // Advances one step of 1 / step_hz. With options.dynamics, the commands
  // act late, the speed lags and the tyres slip (VehicleDynamics); then the
  // speed moves towards speed_command_mps by at most route.max_accel_mps2
  // per second while its
  // magnitude grows and route.max_decel_mps2 while it shrinks (stopping at
  // zero before reversing); the road-wheel angle moves towards its command
  // by at most vehicle.max_road_wheel_rate_radps per second, within
  // +-vehicle.max_road_wheel_angle_rad. Both are held over the step. Then
  // appends to `events`, in time order, the sensor samples due in
  // (t, t + dt] (on the first step [0, dt]), each measured at the true state
  // of its own instant; ties go wheel speed, steering, IMU, slots, tags as
  // in SensorLogSource. Returns the new true state.
  const VehicleState& Step(double speed_command_mps, double road_wheel_angle_command_rad,
                           std::vector<SensorEvent>* events);

  // The hardest the car slows down (m/s^2): by default the route's
  // max_decel_mps2 (a driver's comfort); a controller that must stop (a
  // safety stop) may brake harder. <= 0 restores the route's.
  void SetMaxDecel(double decel_mps2) { max_decel_mps2_ = decel_mps2; }

  // A kidnap: the true pose jumps to T_map_vehicle, speed and steering are
  // kept; the sensors go on from the new pose.
  void Teleport(const SE2& T_map_vehicle);

  const VehicleState& state() const { return state_; }
  const World& world() const { return world_; }
  TimeNs time_ns() const { return state_.t_ns; }
  // Ground truth of the last slot frame: the world slot index of each of
  // its observations, -1 for a false detection. Empty before the first.
  const std::vector<int>& last_slot_labels() const { return last_slot_labels_; }

 private:
  double max_decel_mps2_ = 0.0;  // <= 0: the route's
  // One sensor's sample clock: sample k is due at
  // FromSeconds((k + phase) * period_s), as in the batch simulator.
  struct SampleClock {
    double period_s = 0.0;
    double phase = 0.0;  // in periods
    long next_index = 0;

    TimeNs next_ns() const {
      return FromSeconds((static_cast<double>(next_index) + phase) * period_s);
    }
  };
  enum Sensor { kWheel, kSteering, kImu, kSlots, kTags };
  static constexpr int kSensorCount = 5;

  // The true state at t_ns within the current step: the previous state
  // moved on by the speed and road-wheel angle held over the step.
  VehicleState StateAt(TimeNs t_ns) const;
  // `start` moved on for dt_s at speed_mps with the road wheels at
  // angle_rad, the tyres slipping as options.dynamics says.
  VehicleState Move(const VehicleState& start, double speed_mps, double angle_rad,
                    double dt_s) const;
  SensorEvent Measure(Sensor sensor, const VehicleState& true_state);

  ScenarioConfig scenario_;
  VehicleDynamics dynamics_;
  // Commands waiting for their time to act (actuator delay), and the one
  // acting.
  struct Command {
    TimeNs acts_at_ns = 0;
    double speed_mps = 0.0, angle_rad = 0.0;
  };
  std::deque<Command> pending_;
  Command acting_;
  double step_s_ = 0.0;
  World world_;
  OdometrySensorModel odometry_;
  Random slot_rng_, tag_rng_;
  SampleClock clocks_[kSensorCount];

  long step_index_ = 0;
  VehicleState state_;       // at the end of the last step
  VehicleState step_start_;  // at its start
  std::vector<int> last_slot_labels_;
};

}  // namespace parkslam::sim

#endif  // PARKSLAM_SIM_LIVE_SIMULATOR_H_
