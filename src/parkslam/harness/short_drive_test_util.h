#ifndef PARKSLAM_HARNESS_SHORT_DRIVE_TEST_UTIL_H_
#define PARKSLAM_HARNESS_SHORT_DRIVE_TEST_UTIL_H_

// A short drive for the harness's stream tests: about 30 m along aisle 1
// of the default lot, no laps.

#include <cstdint>

#include "parkslam/common/trajectory.h"
#include "parkslam/sim/simulator.h"

namespace parkslam::harness::test_util {

struct ShortDrive {
  sim::ScenarioConfig scenario;
  sim::Simulation simulation;
  Trajectory truth;
};

inline ShortDrive MakeShortDrive(std::uint64_t seed) {
  ShortDrive d;
  d.scenario = sim::DefaultScenario();
  d.scenario.route.laps = 0;
  d.scenario.route.finish_m = {{40.0, 9.1}};
  d.simulation = sim::Simulate(d.scenario, seed);
  d.truth = sim::GroundTruthTrajectory(d.simulation);
  return d;
}

}  // namespace parkslam::harness::test_util

#endif  // PARKSLAM_HARNESS_SHORT_DRIVE_TEST_UTIL_H_
