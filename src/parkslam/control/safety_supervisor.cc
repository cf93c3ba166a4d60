#include "parkslam/control/safety_supervisor.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace parkslam::control {

bool SafetyOptions::IsValid(std::string* error) const {
  const auto fail = [&](const char* what) {
    if (error != nullptr) *error = what;
    return false;
  };
  if (!(max_position_sigma_m > 0 && std::isfinite(max_position_sigma_m))) {
    return fail("max_position_sigma_m must be positive");
  }
  if (!(max_estimate_age_s > 0 && std::isfinite(max_estimate_age_s))) {
    return fail("max_estimate_age_s must be positive");
  }
  if (!(brake_decel_mps2 > 0 && brake_decel_mps2 <= 10 && go_accel_mps2 > 0 &&
        go_accel_mps2 <= 10)) {
    return fail("brake_decel_mps2 and go_accel_mps2 must be in (0, 10]");
  }
  if (!(resume_after_s >= 0 && std::isfinite(resume_after_s)))
    return fail("resume_after_s must not be negative");
  if (max_rejecting_frames < 1) return fail("max_rejecting_frames must be at least 1");
  return true;
}

SafetySupervisor::SafetySupervisor(const SafetyOptions& options) : options_(options) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument("SafetyOptions: " + error);
}

void SafetySupervisor::OnEstimate(TimeNs t_ns, bool tracking,
                                  const Eigen::Matrix2d& position_covariance, int used,
                                  int rejected) {
  rejecting_frames_ = used == 0 && rejected > 0 ? rejecting_frames_ + 1
                      : used > 0                ? 0
                                                : rejecting_frames_;
  // Held still after a stop, the car sees the same landmarks again and
  // again: their rejection is no new sign of a move, and counting it would
  // keep the car standing for ever where the only landmark in view
  // disagrees with the map. It counts again once the car goes on.
  if (interventions_ > 0 && !stopping_ && allowed_mps_ == 0.0) rejecting_frames_ = 0;
  have_estimate_ = true;
  last_estimate_ns_ = t_ns;
  last_tracking_ = tracking;
  const Eigen::Matrix2d symmetric = 0.5 * (position_covariance + position_covariance.transpose());
  const double largest =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(symmetric, Eigen::EigenvaluesOnly)
          .eigenvalues()
          .maxCoeff();
  last_sigma_m_ = std::isfinite(largest) ? std::sqrt(std::max(0.0, largest)) : INFINITY;
}

bool SafetySupervisor::Healthy(TimeNs t_ns) const {
  return have_estimate_ && last_tracking_ && last_sigma_m_ <= options_.max_position_sigma_m &&
         ToSeconds(t_ns - last_estimate_ns_) <= options_.max_estimate_age_s &&
         rejecting_frames_ < options_.max_rejecting_frames;
}

double SafetySupervisor::AllowedSpeed(TimeNs t_ns, double dt_s, double cruise_mps,
                                      double measured_mps) {
  const bool healthy = Healthy(t_ns);
  if (!healthy && was_healthy_) {
    ++interventions_;
    stopping_ = true;
    // Brake from the speed the car drives: a cap at the cruise speed above
    // it (in a turn, say) would take its time to come down to where it
    // bites (0.3 s from 7 to 10 km/h).
    allowed_mps_ = std::min(allowed_mps_, std::max(0.0, measured_mps));
  }
  if (stopping_ || !healthy) {
    // A loss always ends in a full stop, even if localization comes back
    // at once: a relocalization right after a loss may be wrong.
    allowed_mps_ = std::max(0.0, allowed_mps_ - options_.brake_decel_mps2 * dt_s);
    if (allowed_mps_ == 0.0) stopping_ = false;
    // The wait before going on counts from the stop, and from the return
    // of localization, whichever is later.
    healthy_since_ns_ = healthy && !stopping_ ? t_ns : -1;
  } else {
    if (healthy_since_ns_ < 0) healthy_since_ns_ = t_ns;
    // At the very start the car has never moved: no waiting.
    const bool settled =
        interventions_ == 0 || ToSeconds(t_ns - healthy_since_ns_) >= options_.resume_after_s;
    if (settled) allowed_mps_ = std::min(cruise_mps, allowed_mps_ + options_.go_accel_mps2 * dt_s);
  }
  was_healthy_ = healthy;
  return std::min(allowed_mps_, cruise_mps);
}

}  // namespace parkslam::control
