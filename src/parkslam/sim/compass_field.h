#ifndef PARKSLAM_SIM_COMPASS_FIELD_H_
#define PARKSLAM_SIM_COMPASS_FIELD_H_

// How far a compass is bent at each place of the lot (sensors.compass,
// scenario_config.h). Indoors, steel bends the earth's field: the error of
// a magnetometer heading depends on where the car is, not on the time, so
// a car standing still sees a constant error and a car driving past a
// pillar sees it rise and fall over a few metres.
//
//   d(p) = sum_k a_k exp(-|p - p_k|^2 / (2 r^2))            steel (pillars, parked cars)
//        + sum_{i<3} b_i sin(2 pi u_i . p / lambda + phi_i)  background (rebar, cables)
//
// with a_k ~ N(0, steel_sigma), r = steel_range_m, u_i random unit vectors,
// b_i ~ background_sigma sqrt(2/3) so that the background's spread is
// background_sigma, phi_i uniform. The parked cars stand in a seeded share
// of the slots, at their centres.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "parkslam/sim/scenario_config.h"
#include "parkslam/sim/world.h"

namespace parkslam::sim {

class CompassField {
 public:
  // No disturbance anywhere (the "clean" and "none" models).
  CompassField() = default;
  CompassField(const World& world, const CompassConfig& config, std::uint64_t seed);

  // The heading error at p_map, radians (added to the true yaw).
  double DisturbanceAt(const Eigen::Vector2d& p_map) const;

  int steel_sources() const { return static_cast<int>(steel_.size()); }

 private:
  struct Steel {
    Eigen::Vector2d p_map;
    double amplitude_rad = 0.0;
  };
  struct Wave {
    Eigen::Vector2d k_per_m = Eigen::Vector2d::Zero();  // 2 pi u / lambda
    double amplitude_rad = 0.0;
    double phase_rad = 0.0;
  };
  std::vector<Steel> steel_;
  std::vector<Wave> waves_;
  double inv_two_range_sq_ = 0.0;
  double reach_sq_m2_ = 0.0;  // beyond 4 ranges a source adds < 0.04 % of itself
};

}  // namespace parkslam::sim

#endif  // PARKSLAM_SIM_COMPASS_FIELD_H_
