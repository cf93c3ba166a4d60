#ifndef PARKSLAM_SIM_ROUTE_H_
#define PARKSLAM_SIM_ROUTE_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "parkslam/sensor/vehicle.h"
#include "parkslam/sim/scenario_config.h"
#include "parkslam/sim/simulator.h"

namespace parkslam::sim {

// The waypoints of the route in driving order: approach, `laps` times round
// the closed loop, finish; consecutive duplicates removed.
std::vector<Eigen::Vector2d> RouteWaypoints(const RouteConfig& route);

// Kinematic bicycle model about the rear axle:
//   x' = v cos(yaw), y' = v sin(yaw), yaw' = v tan(delta) / wheelbase.
// One explicit step of dt_s with exact integration along the arc.
VehicleState StepBicycle(const VehicleState& state, double speed_mps, double road_wheel_angle_rad,
                         double dt_s, const VehicleParameters& vehicle);

// A human-like drive along the route: a pure-pursuit driver follows the
// waypoint polyline with a smooth lateral wander, within the vehicle's
// steering limits, with speeds that slow for turns and respect acceleration
// limits; it starts and ends at rest. Deterministic by seed.
std::vector<VehicleState> DriveRoute(const RouteConfig& route, const VehicleParameters& vehicle,
                                     std::uint64_t seed);

}  // namespace parkslam::sim

#endif  // PARKSLAM_SIM_ROUTE_H_
