#ifndef PARKSLAM_CONTROL_SAFETY_SUPERVISOR_H_
#define PARKSLAM_CONTROL_SAFETY_SUPERVISOR_H_

// The car stops when it no longer knows where it is. The paper (IV-B)
// follows a recorded trace on the map's localization; a real car must not
// drive on when that localization is lost or too uncertain.
//
// Healthy at time t when the last localization estimate
//   - tracks (the localizer is neither lost nor uninitialized),
//   - has a position standard deviation sigma = sqrt(lambda_max(P_xy)) at
//     most max_position_sigma_m, and
//   - is no older than max_estimate_age_s (camera frames keep coming), and
//   - is not the last of max_rejecting_frames frames in a row in which the
//     localizer rejected what it saw and accepted nothing (a car that was
//     moved sees its landmarks where the map has none, about a second
//     before the localizer declares itself lost); rejections seen while
//     held still after a stop do not count (the same landmarks again are
//     no new sign of a move).
// The speed the car may drive, v_allowed, follows:
//   unhealthy:                    v_allowed <- max(0, v_allowed - a_brake dt),
//                                 from the measured speed when it starts
//   healthy for resume_after_s:   v_allowed <- min(v_cruise, v_allowed + a_go dt)
// so the car brakes at a comfortable deceleration to a stop and goes on,
// gently, once localization is back and has stayed back. A loss always
// ends in a full stop, even when the localizer relocalizes at once (a
// relocalization right after a loss may be a wrong one).

#include <Eigen/Core>
#include <string>

#include "parkslam/common/time.h"

namespace parkslam::control {

struct SafetyOptions {
  double max_position_sigma_m = 0.5;
  double max_estimate_age_s = 0.6;
  double brake_decel_mps2 = 2.5;  // about a quarter of g: firm, not an emergency stop
  double go_accel_mps2 = 1.0;
  double resume_after_s = 1.0;
  int max_rejecting_frames = 3;

  bool IsValid(std::string* error) const;
};

class SafetySupervisor {
 public:
  // Throws std::invalid_argument for invalid options.
  explicit SafetySupervisor(const SafetyOptions& options = {});

  // One localization estimate at t_ns: whether it tracks, its position
  // covariance (x, y) in m^2, and how many observations of the frame it
  // used and rejected.
  void OnEstimate(TimeNs t_ns, bool tracking, const Eigen::Matrix2d& position_covariance,
                  int used = 1, int rejected = 0);

  // The speed the car may drive at t_ns, after a control step of dt_s,
  // for a wished cruise speed and the speed measured now (m/s).
  double AllowedSpeed(TimeNs t_ns, double dt_s, double cruise_mps, double measured_mps);

  bool Healthy(TimeNs t_ns) const;
  // Whether it is braking the car to a stop now (the brakes may work
  // harder than a driver's comfort limit).
  bool Braking(TimeNs t_ns) const { return stopping_ || !Healthy(t_ns); }
  // Times the car was made to stop (healthy -> unhealthy transitions).
  int interventions() const { return interventions_; }

 private:
  SafetyOptions options_;
  bool have_estimate_ = false;
  TimeNs last_estimate_ns_ = 0;
  bool last_tracking_ = false;
  double last_sigma_m_ = 0.0;
  int rejecting_frames_ = 0;
  TimeNs healthy_since_ns_ = -1;  // -1: not healthy now
  bool was_healthy_ = false;
  bool stopping_ = false;  // braking to a full stop after a loss
  double allowed_mps_ = 0.0;
  int interventions_ = 0;
};

}  // namespace parkslam::control

#endif  // PARKSLAM_CONTROL_SAFETY_SUPERVISOR_H_
