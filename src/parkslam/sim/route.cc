#include "parkslam/sim/route.h"

#include <algorithm>
#include <cmath>

#include "parkslam/common/angles.h"
#include "parkslam/common/random.h"

namespace parkslam::sim {
namespace {

constexpr std::uint64_t kDriverStreamTag = 0xd21;
constexpr double kPathStepM = 0.1;
constexpr double kTurnSlowdownRadiusM = 7.0;  // slow down this close to a turn
constexpr double kTurnAngleRad = 0.35;        // a waypoint this sharp is a turn
// How far ahead along the path the driver looks for the nearest point: far
// enough for one step at any speed, short enough never to jump to a later
// part of the route that passes close by.
constexpr double kNearestSearchM = 2.0;

// The reference path: the route polyline resampled every kPathStepM, with its
// arc length and the speed the driver aims for there.
struct ReferencePath {
  std::vector<Eigen::Vector2d> points_m;
  std::vector<double> target_speed_mps;
  double length_m = 0.0;
};

ReferencePath BuildReferencePath(const RouteConfig& route, Random& rng) {
  const std::vector<Eigen::Vector2d> waypoints = RouteWaypoints(route);
  ReferencePath path;
  std::vector<double> turn_at_s;  // arc lengths of sharp waypoints
  double s0 = 0.0;
  for (size_t i = 0; i + 1 < waypoints.size(); ++i) {
    const Eigen::Vector2d a = waypoints[i], b = waypoints[i + 1];
    const double length_m = (b - a).norm();
    if (i > 0) {
      const Eigen::Vector2d in = a - waypoints[i - 1];
      const double turn =
          std::abs(AngleDiff(std::atan2((b - a).y(), (b - a).x()), std::atan2(in.y(), in.x())));
      if (turn > kTurnAngleRad) turn_at_s.push_back(s0);
    }
    const int steps = std::max(1, static_cast<int>(std::ceil(length_m / kPathStepM)));
    for (int k = 0; k < steps; ++k) {
      path.points_m.push_back(a + (b - a) * (static_cast<double>(k) / steps));
    }
    s0 += length_m;
  }
  path.points_m.push_back(waypoints.back());

  // Human wander: a smooth lateral offset made of two slow sinusoids of
  // random phase, applied along the local left normal.
  const double phase1 = rng.Uniform(0.0, 2 * kPi), phase2 = rng.Uniform(0.0, 2 * kPi);
  const double speed_phase = rng.Uniform(0.0, 2 * kPi);
  std::vector<Eigen::Vector2d> wandered(path.points_m.size());
  std::vector<double> arc(path.points_m.size(), 0.0);
  for (size_t i = 0; i < path.points_m.size(); ++i) {
    if (i > 0) arc[i] = arc[i - 1] + (path.points_m[i] - path.points_m[i - 1]).norm();
    const size_t j = std::min(i + 1, path.points_m.size() - 1);
    const size_t h = j == i ? i - 1 : i;
    const Eigen::Vector2d tangent = (path.points_m[j] - path.points_m[h]).normalized();
    const Eigen::Vector2d left(-tangent.y(), tangent.x());
    const double offset =
        route.lateral_wander_m * (0.6 * std::sin(2 * kPi * arc[i] / 37.0 + phase1) +
                                  0.4 * std::sin(2 * kPi * arc[i] / 13.0 + phase2));
    wandered[i] = path.points_m[i] + offset * left;
  }
  path.points_m = wandered;
  path.length_m = arc.back();

  // Target speeds: cruise, slower near turns, a slow +-5 % human variation,
  // then limited by acceleration forwards and deceleration backwards so the
  // drive starts and ends at rest.
  const double cruise = route.cruise_speed_kmh / 3.6, turn = route.turn_speed_kmh / 3.6;
  const size_t n = path.points_m.size();
  path.target_speed_mps.resize(n);
  for (size_t i = 0; i < n; ++i) {
    double v = cruise * (1.0 + 0.05 * std::sin(2 * kPi * arc[i] / 60.0 + speed_phase));
    for (double s_turn : turn_at_s) {
      if (std::abs(arc[i] - s_turn) < kTurnSlowdownRadiusM) v = std::min(v, turn);
    }
    path.target_speed_mps[i] = v;
  }
  path.target_speed_mps.front() = 0.0;
  path.target_speed_mps.back() = 0.0;
  for (size_t i = 1; i < n; ++i) {
    const double ds = arc[i] - arc[i - 1];
    path.target_speed_mps[i] =
        std::min(path.target_speed_mps[i],
                 std::sqrt(path.target_speed_mps[i - 1] * path.target_speed_mps[i - 1] +
                           2 * route.max_accel_mps2 * ds));
  }
  for (size_t i = n - 1; i-- > 0;) {
    const double ds = arc[i + 1] - arc[i];
    path.target_speed_mps[i] =
        std::min(path.target_speed_mps[i],
                 std::sqrt(path.target_speed_mps[i + 1] * path.target_speed_mps[i + 1] +
                           2 * route.max_decel_mps2 * ds));
  }
  return path;
}

}  // namespace

std::vector<Eigen::Vector2d> RouteWaypoints(const RouteConfig& route) {
  std::vector<Eigen::Vector2d> points = route.approach_m;
  for (int lap = 0; lap < route.laps; ++lap) {
    points.insert(points.end(), route.loop_m.begin(), route.loop_m.end());
  }
  if (route.laps > 0 && !route.loop_m.empty()) points.push_back(route.loop_m.front());
  points.insert(points.end(), route.finish_m.begin(), route.finish_m.end());
  std::vector<Eigen::Vector2d> unique;
  for (const Eigen::Vector2d& p : points) {
    if (unique.empty() || (p - unique.back()).norm() > 1e-6) unique.push_back(p);
  }
  return unique;
}

VehicleState StepBicycle(const VehicleState& state, double speed_mps, double road_wheel_angle_rad,
                         double dt_s, const VehicleParameters& vehicle) {
  const double yaw_rate = speed_mps * std::tan(road_wheel_angle_rad) / vehicle.wheelbase_m;
  const double yaw0 = state.T_map_vehicle.yaw();
  const double dyaw = yaw_rate * dt_s;
  Eigen::Vector2d delta;
  if (std::abs(dyaw) < 1e-9) {
    delta = speed_mps * dt_s * Eigen::Vector2d(std::cos(yaw0), std::sin(yaw0));
  } else {
    const double radius = speed_mps / yaw_rate;
    delta = radius * Eigen::Vector2d(std::sin(yaw0 + dyaw) - std::sin(yaw0),
                                     std::cos(yaw0) - std::cos(yaw0 + dyaw));
  }
  VehicleState next;
  next.t_ns = state.t_ns + FromSeconds(dt_s);
  next.T_map_vehicle = SE2(state.T_map_vehicle.translation() + delta, yaw0 + dyaw);
  next.speed_mps = speed_mps;
  next.road_wheel_angle_rad = road_wheel_angle_rad;
  next.yaw_rate_radps = yaw_rate;
  return next;
}

std::vector<VehicleState> DriveRoute(const RouteConfig& route, const VehicleParameters& vehicle,
                                     std::uint64_t seed) {
  Random rng = Random::Derive(seed, kDriverStreamTag);
  const ReferencePath path = BuildReferencePath(route, rng);
  const double dt_s = 1.0 / route.sample_rate_hz;
  const TimeNs dt_ns = FromSeconds(dt_s);
  const size_t n = path.points_m.size();

  VehicleState state;
  const Eigen::Vector2d first_dir = path.points_m[std::min<size_t>(10, n - 1)] - path.points_m[0];
  state.T_map_vehicle = SE2(path.points_m[0], std::atan2(first_dir.y(), first_dir.x()));
  std::vector<VehicleState> states{state};

  size_t nearest = 0;
  double speed = 0.0, steer = 0.0;
  const double max_steps =
      10.0 * path.length_m / (route.turn_speed_kmh / 3.6) / dt_s + 10.0 * route.sample_rate_hz;
  for (int step = 0; step < max_steps; ++step) {
    const Eigen::Vector2d p = state.T_map_vehicle.translation();
    // Advance the nearest path index along the path (never backwards).
    const size_t search_end =
        std::min(n, nearest + static_cast<size_t>(kNearestSearchM / kPathStepM));
    for (size_t i = nearest; i < search_end; ++i) {
      if ((path.points_m[i] - p).squaredNorm() < (path.points_m[nearest] - p).squaredNorm()) {
        nearest = i;
      }
    }
    const double remaining_m = static_cast<double>(n - 1 - nearest) * kPathStepM;
    if (remaining_m < 0.6 && speed < 0.05) break;

    // Pure pursuit: steer onto the arc through a point lookahead ahead.
    const double lookahead_m = route.lookahead_m + 0.5 * speed;
    const size_t target = std::min(n - 1, nearest + static_cast<size_t>(lookahead_m / kPathStepM));
    const Eigen::Vector2d to_target = state.T_map_vehicle.inverse() * path.points_m[target];
    const double distance = std::max(to_target.norm(), 0.5);
    const double steer_cmd =
        std::atan(2.0 * vehicle.wheelbase_m * to_target.y() / (distance * distance));
    const double max_delta = vehicle.max_road_wheel_rate_radps * dt_s;
    steer += std::clamp(steer_cmd - steer, -max_delta, max_delta);
    steer = std::clamp(steer, -vehicle.max_road_wheel_angle_rad, vehicle.max_road_wheel_angle_rad);

    // Speed: aim at the profile half a metre ahead, within the limits.
    const size_t ahead = std::min(n - 1, nearest + 5);
    const double speed_cmd = remaining_m < 0.6 ? 0.0 : std::max(path.target_speed_mps[ahead], 0.15);
    speed +=
        std::clamp(speed_cmd - speed, -route.max_decel_mps2 * dt_s, route.max_accel_mps2 * dt_s);
    speed = std::max(speed, 0.0);

    state = StepBicycle(state, speed, steer, dt_s, vehicle);
    state.t_ns = states.back().t_ns + dt_ns;
    states.push_back(state);
  }
  return states;
}

}  // namespace parkslam::sim
