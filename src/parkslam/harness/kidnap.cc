#include "parkslam/harness/kidnap.h"

#include <stdexcept>

#include "parkslam/common/angles.h"
#include "parkslam/common/random.h"

namespace parkslam::harness {
namespace {

constexpr std::uint64_t kKidnapTag = 0x6b1d;
constexpr double kSettleS = 10.0;  // tracking time before a kidnap

}  // namespace

KidnapResult RunKidnapTrials(const SemanticMap& map, const SensorLog& log, const Trajectory& truth,
                             const localization::LocalizerOptions& localizer_options,
                             const odometry::OdometryEkfOptions& odometry_options,
                             const KidnapOptions& options,
                             const std::function<void(int done, int total)>& on_trial_done) {
  if (truth.size() < 2) throw std::invalid_argument("kidnap trials need a ground-truth drive");
  const TimeNs start = truth.front().t_ns, end = truth.back().t_ns;
  const double duration_s = ToSeconds(end - start);
  if (duration_s < kSettleS + 2 * options.max_recovery_s) {
    throw std::invalid_argument("kidnap trials need a drive longer than 20 s");
  }
  Random rng = Random::Derive(options.seed, kKidnapTag);
  KidnapResult result;
  for (int trial = 0; trial < options.trials; ++trial) {
    // Kidnap at a random time, to a random place of the drive far from here.
    const TimeNs kidnap_ns =
        start + FromSeconds(rng.Uniform(kSettleS, duration_s - 2 * options.max_recovery_s));
    const SE2 true_pose = *PoseAt(truth, kidnap_ns);
    SE2 wrong;
    do {
      const TimeNs other = start + FromSeconds(rng.Uniform(0.0, duration_s));
      wrong = SE2(PoseAt(truth, other)->translation(), rng.Uniform(-kPi, kPi));
    } while ((wrong.translation() - true_pose.translation()).norm() < 5.0);

    localization::Localizer localizer(map, localizer_options, odometry_options);
    localizer.SetPose(truth.front().T_map_vehicle, Eigen::Vector3d(0.01, 0.01, 0.001).asDiagonal());
    SensorLogSource source(log);
    bool kidnapped = false, noticed = false, recovered = false;
    double driving_s = 0.0;
    TimeNs last_ns = start;
    double speed = 0.0;
    while (const auto event = source.Next()) {
      if (const auto* w = std::get_if<WheelSpeed>(&*event)) speed = w->speed_mps;
      const TimeNs t_ns = EventTime(*event);
      if (kidnapped && speed > options.moving_speed_mps) driving_s += ToSeconds(t_ns - last_ns);
      last_ns = t_ns;
      const auto estimate = localizer.Process(*event);
      if (!estimate) continue;
      if (!kidnapped) {
        if (t_ns >= kidnap_ns) {
          localizer.SetPose(wrong, Eigen::Vector3d(0.01, 0.01, 0.001).asDiagonal());
          kidnapped = true;
        }
        continue;
      }
      noticed |= estimate->state == localization::LocalizerState::kLost;
      if (noticed && estimate->state == localization::LocalizerState::kTracking) {
        const double error =
            (PoseAt(truth, t_ns)->translation() - estimate->T_map_vehicle.translation()).norm();
        if (error < options.success_error_m) {
          recovered = true;
          break;
        }
      }
      if (driving_s > options.max_recovery_s) break;
    }
    ++result.trials;
    if (recovered && driving_s <= options.max_recovery_s) {
      ++result.successes;
      result.recovery_s.push_back(driving_s);
    }
    if (on_trial_done) on_trial_done(trial + 1, options.trials);
  }
  return result;
}

}  // namespace parkslam::harness
