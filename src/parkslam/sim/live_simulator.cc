#include "parkslam/sim/live_simulator.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "parkslam/sim/route.h"

namespace parkslam::sim {
namespace {

// The scenario, once it and the options are checked; throws otherwise.
const ScenarioConfig& Validated(const ScenarioConfig& scenario,
                                const LiveSimulatorOptions& options) {
  std::string error;
  if (!scenario.IsValid(&error) || !options.IsValid(&error)) {
    throw std::invalid_argument(error);
  }
  return scenario;
}

// The speed after one step towards `command_mps`: its magnitude grows by at
// most max_accel_step_mps and shrinks by at most max_decel_step_mps; a
// command to reverse first brings the car to rest.
double LimitSpeed(double speed_mps, double command_mps, double max_accel_step_mps,
                  double max_decel_step_mps) {
  if (speed_mps > 0.0 && command_mps < speed_mps) {
    return std::max({speed_mps - max_decel_step_mps, command_mps, 0.0});
  }
  if (speed_mps < 0.0 && command_mps > speed_mps) {
    return std::min({speed_mps + max_decel_step_mps, command_mps, 0.0});
  }
  return speed_mps + std::clamp(command_mps - speed_mps, -max_accel_step_mps, max_accel_step_mps);
}

// The road-wheel angle after one step towards `command_rad`, within the
// vehicle's rate and angle limits.
double LimitSteering(double angle_rad, double command_rad, double dt_s,
                     const VehicleParameters& vehicle) {
  const double max_angle = vehicle.max_road_wheel_angle_rad;
  const double max_step = vehicle.max_road_wheel_rate_radps * dt_s;
  const double target = std::clamp(command_rad, -max_angle, max_angle);
  return std::clamp(angle_rad + std::clamp(target - angle_rad, -max_step, max_step), -max_angle,
                    max_angle);
}

}  // namespace

bool VehicleDynamics::IsValid(std::string* error) const {
  const auto in = [](double v, double hi) { return std::isfinite(v) && v >= 0.0 && v <= hi; };
  if (in(actuator_delay_s, 2.0) && in(speed_lag_s, 10.0) &&
      in(understeer_gradient_rad_per_mps2, 0.1) && in(sideslip_rad_per_mps2, 0.1)) {
    return true;
  }
  if (error != nullptr) {
    *error =
        "dynamics: actuator_delay_s in [0, 2], speed_lag_s in [0, 10], "
        "understeer_gradient_rad_per_mps2 and sideslip_rad_per_mps2 in [0, 0.1]";
  }
  return false;
}

VehicleDynamics RealisticDynamics() {
  VehicleDynamics d;
  d.actuator_delay_s = 0.15;
  d.speed_lag_s = 0.5;
  d.understeer_gradient_rad_per_mps2 = 0.004;
  d.sideslip_rad_per_mps2 = 0.005;
  return d;
}

bool LiveSimulatorOptions::IsValid(std::string* error) const {
  if (!(std::isfinite(step_hz) && step_hz >= 1.0 && step_hz <= 10000.0)) {
    if (error != nullptr) *error = "step_hz: must be in [1, 10000]";
    return false;
  }
  return dynamics.IsValid(error);
}

LiveSimulator::LiveSimulator(const ScenarioConfig& scenario, std::uint64_t seed,
                             const SE2& T_map_vehicle_start, const LiveSimulatorOptions& options)
    : scenario_(Validated(scenario, options)),
      dynamics_(options.dynamics),
      step_s_(1.0 / options.step_hz),
      world_(BuildWorld(scenario.world)),
      odometry_(MakeOdometrySensorModel(scenario.sensors, scenario.vehicle, world_, seed)),
      slot_rng_(Random::Derive(seed, kSlotFrameStreamTag)),
      tag_rng_(Random::Derive(seed, kTagFrameStreamTag)) {
  const OdometrySensorConfig& odometry = scenario_.sensors.odometry;
  clocks_[kWheel].period_s = 1.0 / odometry.wheel_rate_hz;
  clocks_[kSteering].period_s = 1.0 / odometry.steering_rate_hz;
  clocks_[kImu].period_s = 1.0 / odometry.imu_rate_hz;
  clocks_[kSlots].period_s = 1.0 / scenario_.sensors.slots.rate_hz;
  // Half a period late, as two unsynchronised cameras (see Simulate).
  clocks_[kTags].period_s = 1.0 / scenario_.sensors.tags.rate_hz;
  clocks_[kTags].phase = 0.5;
  state_.T_map_vehicle = T_map_vehicle_start;
  step_start_ = state_;
}

const VehicleState& LiveSimulator::Step(double speed_command_mps,
                                        double road_wheel_angle_command_rad,
                                        std::vector<SensorEvent>* events) {
  const RouteConfig& limits = scenario_.route;
  // The command that acts now: the latest whose delay has passed.
  pending_.push_back({state_.t_ns + FromSeconds(dynamics_.actuator_delay_s), speed_command_mps,
                      road_wheel_angle_command_rad});
  while (!pending_.empty() && pending_.front().acts_at_ns <= state_.t_ns) {
    acting_ = pending_.front();
    pending_.pop_front();
  }
  double speed_target = acting_.speed_mps;
  if (dynamics_.speed_lag_s > 0.0) {
    speed_target = state_.speed_mps + (acting_.speed_mps - state_.speed_mps) *
                                          (1.0 - std::exp(-step_s_ / dynamics_.speed_lag_s));
  }
  const double speed_mps =
      LimitSpeed(state_.speed_mps, speed_target, limits.max_accel_mps2 * step_s_,
                 (max_decel_mps2_ > 0.0 ? max_decel_mps2_ : limits.max_decel_mps2) * step_s_);
  const double angle_rad =
      LimitSteering(state_.road_wheel_angle_rad, acting_.angle_rad, step_s_, scenario_.vehicle);
  step_start_ = state_;
  ++step_index_;
  state_ = Move(step_start_, speed_mps, angle_rad, step_s_);
  state_.t_ns = FromSeconds(static_cast<double>(step_index_) * step_s_);

  // Emit the due samples earliest first; ties in the order of Sensor.
  for (;;) {
    int due = -1;
    TimeNs due_ns = 0;
    for (int s = 0; s < kSensorCount; ++s) {
      const TimeNs t_ns = clocks_[s].next_ns();
      if (t_ns <= state_.t_ns && (due < 0 || t_ns < due_ns)) {
        due = s;
        due_ns = t_ns;
      }
    }
    if (due < 0) break;
    events->push_back(Measure(static_cast<Sensor>(due), StateAt(due_ns)));
    ++clocks_[due].next_index;
  }
  return state_;
}

void LiveSimulator::Teleport(const SE2& T_map_vehicle) { state_.T_map_vehicle = T_map_vehicle; }

VehicleState LiveSimulator::StateAt(TimeNs t_ns) const {
  if (t_ns >= state_.t_ns) return state_;
  if (t_ns <= step_start_.t_ns) return step_start_;
  VehicleState s = Move(step_start_, state_.speed_mps, state_.road_wheel_angle_rad,
                        ToSeconds(t_ns - step_start_.t_ns));
  s.t_ns = t_ns;
  return s;
}

VehicleState LiveSimulator::Move(const VehicleState& start, double speed_mps, double angle_rad,
                                 double dt_s) const {
  const VehicleParameters& vehicle = scenario_.vehicle;
  if (dynamics_.understeer_gradient_rad_per_mps2 == 0.0 && dynamics_.sideslip_rad_per_mps2 == 0.0) {
    return StepBicycle(start, speed_mps, angle_rad, dt_s, vehicle);
  }
  // Lateral acceleration of the kinematic turn, v^2 tan(delta) / L; the
  // angle that acts is smaller by the understeer (never past straight).
  const double lateral_mps2 = speed_mps * speed_mps * std::tan(angle_rad) / vehicle.wheelbase_m;
  const double lost = dynamics_.understeer_gradient_rad_per_mps2 * std::abs(lateral_mps2);
  const double acting =
      angle_rad > 0.0 ? std::max(0.0, angle_rad - lost) : std::min(0.0, angle_rad + lost);
  VehicleState next = StepBicycle(start, speed_mps, acting, dt_s, vehicle);
  // The body moves outwards of its heading: the displacement turns by the
  // sideslip angle, away from the turn's centre.
  const double sideslip = -dynamics_.sideslip_rad_per_mps2 * speed_mps * next.yaw_rate_radps;
  const Eigen::Vector2d moved =
      next.T_map_vehicle.translation() - start.T_map_vehicle.translation();
  const Eigen::Vector2d slipped = Eigen::Rotation2Dd(sideslip) * moved;
  next.T_map_vehicle = SE2(start.T_map_vehicle.translation() + slipped, next.T_map_vehicle.yaw());
  next.road_wheel_angle_rad = angle_rad;  // what the steering sensor reads
  return next;
}

SensorEvent LiveSimulator::Measure(Sensor sensor, const VehicleState& true_state) {
  const TimeNs t_ns = true_state.t_ns;
  switch (sensor) {
    case kWheel:
      return odometry_.MeasureWheel(true_state, t_ns);
    case kSteering:
      return odometry_.MeasureSteering(true_state, t_ns);
    case kImu:
      return odometry_.MeasureImu(true_state, t_ns, clocks_[kImu].period_s);
    case kSlots:
      return SimulateSlotFrame(world_, true_state.T_map_vehicle, t_ns, scenario_.sensors, slot_rng_,
                               &last_slot_labels_);
    case kTags:
      break;
  }
  return SimulateTagFrame(world_, true_state.T_map_vehicle, t_ns, scenario_.sensors.tags, tag_rng_);
}

}  // namespace parkslam::sim
