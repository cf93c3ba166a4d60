#ifndef PARKSLAM_CONTROL_PATH_FOLLOWER_H_
#define PARKSLAM_CONTROL_PATH_FOLLOWER_H_

#include <string>

#include "parkslam/common/se2.h"
#include "parkslam/control/trace.h"
#include "parkslam/sensor/vehicle.h"

namespace parkslam::control {

struct PathFollowerOptions {
  // Pure-pursuit look-ahead along the trace: base + per_mps * speed.
  double lookahead_base_m = 2.0;
  double lookahead_per_mps = 0.6;
  // Speed limits: v <= sqrt(max_lateral_accel / curvature) ahead, and the
  // commanded speed changes by at most max_accel / max_decel * dt per update.
  double max_lateral_accel_mps2 = 1.0;
  double max_accel_mps2 = 0.5;
  double max_decel_mps2 = 0.8;
  // Finished within this distance of the trace end at a speed below
  // stop_speed_mps.
  double stop_distance_m = 0.3;
  double stop_speed_mps = 0.05;
  // Progress is projected within +-search_window_m of the previous progress.
  double search_window_m = 5.0;
  // The speed limit takes the largest curvature from curvature_lookbehind_m
  // behind the progress (the rear axle, where progress is measured, lags the
  // body through a turn) to curvature_horizon_m ahead of it.
  double curvature_horizon_m = 5.0;
  double curvature_lookbehind_m = 1.0;

  bool IsValid(std::string* error) const;

  // The field list, walked by the options file reader (io/options_yaml.h).
  template <typename V>
  void VisitFields(V& v) {
    v("lookahead_base_m", lookahead_base_m);
    v("lookahead_per_mps", lookahead_per_mps);
    v("max_lateral_accel_mps2", max_lateral_accel_mps2);
    v("max_accel_mps2", max_accel_mps2);
    v("max_decel_mps2", max_decel_mps2);
    v("stop_distance_m", stop_distance_m);
    v("stop_speed_mps", stop_speed_mps);
    v("search_window_m", search_window_m);
    v("curvature_horizon_m", curvature_horizon_m);
    v("curvature_lookbehind_m", curvature_lookbehind_m);
  }
};

// Follows a Trace with pure pursuit and a speed profile (paper IV-B: the car
// drives the recorded trace autonomously). Steering acts about the rear axle
// of a kinematic bicycle. Stateful: it keeps its progress along the trace
// (monotone), the last commanded steering (rate limit, starts at 0) and the
// last commanded speed (acceleration limits, starts at the first measured
// speed). One instance per drive.
class PathFollower {
 public:
  // Throws std::invalid_argument on invalid options or vehicle parameters.
  PathFollower(const Trace& trace, const VehicleParameters& vehicle,
               const PathFollowerOptions& options = {});

  struct Command {
    double speed_mps = 0.0;
    double road_wheel_angle_rad = 0.0;
    bool finished = false;
    // Progress along the trace and the signed (left positive) offset from it.
    double s_m = 0.0;
    double lateral_error_m = 0.0;
  };

  // T_map_vehicle: the estimated pose of the rear axle. Throws
  // std::invalid_argument for dt_s <= 0 or a negative cruise speed. Once
  // finished, commands stay finished at zero speed.
  Command Update(const SE2& T_map_vehicle, double current_speed_mps, double dt_s,
                 double cruise_speed_mps);

  const Trace& trace() const { return trace_; }

 private:
  // Distance left to the trace end along the trace; negative past the end.
  double RemainingM(const Trace::Projection& projection, const Eigen::Vector2d& p) const;
  // The trace point `distance_m` ahead of the progress, continued straight
  // past the end so the steering stays defined there.
  Eigen::Vector2d LookaheadPoint(double distance_m) const;
  // Pure pursuit: delta = atan(2 L sin(alpha) / l_d).
  double PurePursuitAngle(const SE2& T_map_vehicle, const Eigen::Vector2d& target_map) const;
  // The highest speed allowed by the curvature ahead and the distance left.
  double SpeedLimit(double remaining_m) const;

  Trace trace_;
  VehicleParameters vehicle_;
  PathFollowerOptions options_;
  bool started_ = false;
  bool finished_ = false;
  double s_m_ = 0.0;
  double speed_command_mps_ = 0.0;
  double steering_command_rad_ = 0.0;
};

}  // namespace parkslam::control

#endif  // PARKSLAM_CONTROL_PATH_FOLLOWER_H_
