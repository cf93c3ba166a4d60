#ifndef PARKSLAM_HARNESS_KIDNAP_H_
#define PARKSLAM_HARNESS_KIDNAP_H_

#include <cstdint>
#include <functional>
#include <vector>

#include "parkslam/common/trajectory.h"
#include "parkslam/localization/localizer.h"
#include "parkslam/map/semantic_map.h"
#include "parkslam/odometry/odometry_ekf.h"
#include "parkslam/sensor/sensor_log.h"

namespace parkslam::harness {

// Kidnapped-robot trials on a recorded drive: the localizer tracks the drive
// until, at a random time, its belief is replaced by a confident wrong pose
// (a random place of the drive, a random heading), as if the car had been
// carried off. A trial succeeds when the localizer notices (lost) and is
// tracking again within 0.5 m of the truth within max_recovery_s of driving
// (time with the car moving).
struct KidnapOptions {
  int trials = 50;
  std::uint64_t seed = 1;
  double max_recovery_s = 5.0;
  double success_error_m = 0.5;
  double moving_speed_mps = 0.2;
};

struct KidnapResult {
  int trials = 0;
  int successes = 0;
  std::vector<double> recovery_s;  // driving time to recover, successful trials
  double success_rate() const { return trials > 0 ? static_cast<double>(successes) / trials : 0.0; }
};

// `truth` is the drive's ground truth in the map frame (the caller aligns it).
KidnapResult RunKidnapTrials(const SemanticMap& map, const SensorLog& log, const Trajectory& truth,
                             const localization::LocalizerOptions& localizer_options,
                             const odometry::OdometryEkfOptions& odometry_options,
                             const KidnapOptions& options,
                             const std::function<void(int done, int total)>& on_trial_done = {});

}  // namespace parkslam::harness

#endif  // PARKSLAM_HARNESS_KIDNAP_H_
