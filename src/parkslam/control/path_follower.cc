#include "parkslam/control/path_follower.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "parkslam/common/field_checker.h"

namespace parkslam::control {
namespace {

// Spacing of the curvature samples over the horizon ahead.
constexpr double kCurvatureSampleM = 0.25;

}  // namespace

bool PathFollowerOptions::IsValid(std::string* error) const {
  FieldChecker c(error);
  c.Positive(lookahead_base_m, "lookahead_base_m");
  c.NonNegative(lookahead_per_mps, "lookahead_per_mps");
  c.Positive(max_lateral_accel_mps2, "max_lateral_accel_mps2");
  c.Positive(max_accel_mps2, "max_accel_mps2");
  c.Positive(max_decel_mps2, "max_decel_mps2");
  c.Positive(stop_distance_m, "stop_distance_m");
  c.Positive(stop_speed_mps, "stop_speed_mps");
  c.Positive(search_window_m, "search_window_m");
  c.NonNegative(curvature_horizon_m, "curvature_horizon_m");
  c.NonNegative(curvature_lookbehind_m, "curvature_lookbehind_m");
  return c.ok();
}

PathFollower::PathFollower(const Trace& trace, const VehicleParameters& vehicle,
                           const PathFollowerOptions& options)
    : trace_(trace), vehicle_(vehicle), options_(options) {
  std::string error;
  if (!options_.IsValid(&error)) throw std::invalid_argument(error);
  if (!vehicle_.IsValid(&error)) throw std::invalid_argument(error);
}

double PathFollower::RemainingM(const Trace::Projection& projection,
                                const Eigen::Vector2d& p) const {
  const double length_m = trace_.length_m();
  if (projection.s_m < length_m) return length_m - s_m_;
  // Projected onto the end: how far past it along the final direction.
  const double heading = trace_.HeadingAt(length_m);
  const Eigen::Vector2d end_direction(std::cos(heading), std::sin(heading));
  return -std::max(0.0, (p - trace_.PointAt(length_m)).dot(end_direction));
}

Eigen::Vector2d PathFollower::LookaheadPoint(double distance_m) const {
  const double s = s_m_ + distance_m;
  const double length_m = trace_.length_m();
  if (s <= length_m) return trace_.PointAt(s);
  const double heading = trace_.HeadingAt(length_m);
  return trace_.PointAt(length_m) +
         (s - length_m) * Eigen::Vector2d(std::cos(heading), std::sin(heading));
}

double PathFollower::PurePursuitAngle(const SE2& T_map_vehicle,
                                      const Eigen::Vector2d& target_map) const {
  const Eigen::Vector2d target_vehicle = T_map_vehicle.inverse() * target_map;
  const double lookahead_m = target_vehicle.norm();
  if (lookahead_m < 1e-6) return steering_command_rad_;
  const double alpha = std::atan2(target_vehicle.y(), target_vehicle.x());
  return std::atan(2.0 * vehicle_.wheelbase_m * std::sin(alpha) / lookahead_m);
}

double PathFollower::SpeedLimit(double remaining_m) const {
  // Lateral acceleration v^2 * kappa <= a_lat over the road ahead.
  double max_curvature = 0.0;
  const double end_m = std::min(s_m_ + options_.curvature_horizon_m, trace_.length_m());
  for (double s = std::max(0.0, s_m_ - options_.curvature_lookbehind_m);; s += kCurvatureSampleM) {
    max_curvature = std::max(max_curvature, std::abs(trace_.CurvatureAt(std::min(s, end_m))));
    if (s >= end_m) break;
  }
  double limit = max_curvature > 0.0 ? std::sqrt(options_.max_lateral_accel_mps2 / max_curvature)
                                     : std::numeric_limits<double>::infinity();
  // Able to stop at the end: v <= sqrt(2 a_dec d).
  limit = std::min(limit, std::sqrt(2.0 * options_.max_decel_mps2 * std::max(0.0, remaining_m)));
  return limit;
}

PathFollower::Command PathFollower::Update(const SE2& T_map_vehicle, double current_speed_mps,
                                           double dt_s, double cruise_speed_mps) {
  if (!(dt_s > 0.0)) throw std::invalid_argument("PathFollower::Update: dt_s must be > 0");
  if (!(cruise_speed_mps >= 0.0)) {
    throw std::invalid_argument("PathFollower::Update: cruise_speed_mps must be >= 0");
  }
  if (!started_) {
    speed_command_mps_ = std::max(0.0, current_speed_mps);
    started_ = true;
  }

  // Progress: the closest trace point near the previous progress, never back.
  const Eigen::Vector2d& p = T_map_vehicle.translation();
  const Trace::Projection projection = trace_.Project(p, s_m_, options_.search_window_m);
  s_m_ = std::max(s_m_, projection.s_m);
  const double remaining_m = RemainingM(projection, p);

  // Steering: pure pursuit, clamped and rate limited.
  const double lookahead_m =
      options_.lookahead_base_m + options_.lookahead_per_mps * std::abs(current_speed_mps);
  const double max_step_rad = vehicle_.max_road_wheel_rate_radps * dt_s;
  const double wanted_rad =
      std::clamp(PurePursuitAngle(T_map_vehicle, LookaheadPoint(lookahead_m)),
                 -vehicle_.max_road_wheel_angle_rad, vehicle_.max_road_wheel_angle_rad);
  steering_command_rad_ = std::clamp(wanted_rad, steering_command_rad_ - max_step_rad,
                                     steering_command_rad_ + max_step_rad);

  // Speed: cruise within the limits, then the acceleration limits.
  finished_ = finished_ || (remaining_m < options_.stop_distance_m &&
                            std::abs(current_speed_mps) < options_.stop_speed_mps);
  const double wanted_mps = finished_ ? 0.0 : std::min(cruise_speed_mps, SpeedLimit(remaining_m));
  speed_command_mps_ =
      std::clamp(wanted_mps, std::max(0.0, speed_command_mps_ - options_.max_decel_mps2 * dt_s),
                 speed_command_mps_ + options_.max_accel_mps2 * dt_s);

  Command command;
  command.speed_mps = speed_command_mps_;
  command.road_wheel_angle_rad = steering_command_rad_;
  command.finished = finished_;
  command.s_m = s_m_;
  command.lateral_error_m = projection.lateral_m;
  return command;
}

}  // namespace parkslam::control
