#include "parkslam/sim/compass_field.h"

#include <cmath>

#include "parkslam/common/random.h"

namespace parkslam::sim {
namespace {

// The field draws from its own stream, so that adding it moves no other
// sensor's draws.
constexpr std::uint64_t kCompassFieldStreamTag = 0x104;
constexpr double kDegToRad = M_PI / 180.0;
constexpr int kBackgroundWaves = 3;

}  // namespace

CompassField::CompassField(const World& world, const CompassConfig& config, std::uint64_t seed) {
  if (config.model != "disturbed") return;
  Random rng = Random::Derive(seed, kCompassFieldStreamTag);
  const double steel_sigma_rad = config.steel_sigma_deg * kDegToRad;
  for (const WorldPillar& pillar : world.pillars) {
    steel_.push_back({pillar.center_map, rng.Gaussian(steel_sigma_rad)});
  }
  for (const WorldSlot& slot : world.slots) {
    // Both draws always, so the share moves no other slot's car.
    const bool parked = rng.Bernoulli(config.parked_car_share);
    const double amplitude_rad = rng.Gaussian(steel_sigma_rad);
    if (!parked) continue;
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (const Eigen::Vector2d& c : slot.corners_map) centre += 0.25 * c;
    steel_.push_back({centre, amplitude_rad});
  }
  const double wave_amplitude_rad =
      config.background_sigma_deg * kDegToRad * std::sqrt(2.0 / kBackgroundWaves);
  for (int i = 0; i < kBackgroundWaves; ++i) {
    const double direction_rad = rng.Uniform(0.0, 2.0 * M_PI);
    Wave wave;
    wave.k_per_m = 2.0 * M_PI / config.background_wavelength_m *
                   Eigen::Vector2d(std::cos(direction_rad), std::sin(direction_rad));
    wave.amplitude_rad = wave_amplitude_rad;
    wave.phase_rad = rng.Uniform(0.0, 2.0 * M_PI);
    waves_.push_back(wave);
  }
  inv_two_range_sq_ = 1.0 / (2.0 * config.steel_range_m * config.steel_range_m);
  reach_sq_m2_ = 16.0 * config.steel_range_m * config.steel_range_m;
}

double CompassField::DisturbanceAt(const Eigen::Vector2d& p_map) const {
  double d_rad = 0.0;
  for (const Steel& s : steel_) {
    const double r_sq = (p_map - s.p_map).squaredNorm();
    if (r_sq < reach_sq_m2_) d_rad += s.amplitude_rad * std::exp(-r_sq * inv_two_range_sq_);
  }
  for (const Wave& w : waves_)
    d_rad += w.amplitude_rad * std::sin(w.k_per_m.dot(p_map) + w.phase_rad);
  return d_rad;
}

}  // namespace parkslam::sim
