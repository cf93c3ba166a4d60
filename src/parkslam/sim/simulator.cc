#include "parkslam/sim/simulator.h"

#include <stdexcept>

#include "parkslam/common/random.h"
#include "parkslam/sim/route.h"
#include "parkslam/sim/sensor_models.h"

namespace parkslam::sim {
namespace {

constexpr std::uint64_t kSlotTag = 0x201, kTagTag = 0x202;

}  // namespace

Simulation Simulate(const ScenarioConfig& config, std::uint64_t seed) {
  std::string error;
  if (!config.IsValid(&error)) throw std::invalid_argument(error);

  Simulation sim;
  sim.world = BuildWorld(config.world);
  sim.states = DriveRoute(config.route, config.vehicle, seed);
  SimulateOdometrySensors(sim.states,
                          MakeOdometrySensorModel(config.sensors, config.vehicle, sim.world, seed),
                          &sim.log);

  const Trajectory truth = GroundTruthTrajectory(sim);
  const TimeNs start = truth.front().t_ns, end = truth.back().t_ns;
  Random slot_rng = Random::Derive(seed, kSlotTag);
  const double slot_period_s = 1.0 / config.sensors.slots.rate_hz;
  for (long k = 0;; ++k) {
    const TimeNs t = start + FromSeconds(k * slot_period_s);
    if (t > end) break;
    const SE2 pose = *PoseAt(truth, t);
    std::vector<int> labels;
    sim.log.slot_frames.push_back(
        SimulateSlotFrame(sim.world, pose, t, config.sensors, slot_rng, &labels));
    sim.slot_labels.push_back(std::move(labels));
  }
  // Tag frames run half a period after the slot frames, as two unsynchronised
  // cameras would.
  Random tag_rng = Random::Derive(seed, kTagTag);
  const double tag_period_s = 1.0 / config.sensors.tags.rate_hz;
  for (long k = 0;; ++k) {
    const TimeNs t = start + FromSeconds((k + 0.5) * tag_period_s);
    if (t > end) break;
    const SE2 pose = *PoseAt(truth, t);
    sim.log.tag_frames.push_back(
        SimulateTagFrame(sim.world, pose, t, config.sensors.tags, tag_rng));
  }
  return sim;
}

Trajectory GroundTruthTrajectory(const Simulation& simulation) {
  Trajectory trajectory;
  trajectory.reserve(simulation.states.size());
  for (const VehicleState& s : simulation.states) {
    trajectory.push_back({s.t_ns, s.T_map_vehicle});
  }
  return trajectory;
}

}  // namespace parkslam::sim
