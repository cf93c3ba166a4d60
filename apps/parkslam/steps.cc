#include "steps.h"

#include <cstdio>

#include "commands.h"
#include "parkslam/common/angles.h"
#include "parkslam/sim/simulator.h"

namespace parkslam::app {

io::Dataset SimulateDataset(const sim::ScenarioConfig& scenario, std::uint64_t seed) {
  sim::Simulation simulation = sim::Simulate(scenario, seed);
  io::Dataset dataset;
  dataset.name = scenario.world.name + "-seed" + std::to_string(seed);
  dataset.seed = seed;
  dataset.created_by = std::string("parkslam simulate ") + kVersion;
  dataset.scenario = scenario;
  dataset.groundtruth_trajectory = sim::GroundTruthTrajectory(simulation);
  dataset.groundtruth_map = sim::ToSemanticMap(simulation.world);
  dataset.groundtruth_map->metadata["seed"] = std::to_string(seed);
  dataset.log = std::move(simulation.log);
  dataset.slot_labels = std::move(simulation.slot_labels);
  return dataset;
}

pipeline::DeadReckoningResult RunOdometry(const io::Dataset& dataset,
                                          const pipeline::DeadReckoningOptions& options) {
  SensorLogSource source(dataset.log);
  return pipeline::RunDeadReckoning(
      source,
      pipeline::EkfOptionsFromSensorSpec(dataset.scenario.sensors.odometry,
                                         dataset.scenario.vehicle),
      options);
}

nlohmann::json MetricsToJson(const eval::TrajectoryMetrics& m) {
  nlohmann::json j;
  j["matched_poses"] = m.matched_poses;
  j["length_m"] = m.length_m;
  j["ate_rmse_m"] = m.ate_rmse_m;
  j["ate_mean_m"] = m.ate_mean_m;
  j["ate_max_m"] = m.ate_max_m;
  j["yaw_rmse_deg"] = RadToDeg(m.yaw_rmse_rad);
  j["yaw_max_deg"] = RadToDeg(m.yaw_max_rad);
  j["rpe_10m_trans_rmse_m"] = m.rpe_trans_rmse_m;
  j["rpe_10m_yaw_rmse_deg"] = RadToDeg(m.rpe_yaw_rmse_rad);
  // NaN (path shorter than 100 m) becomes null.
  j["drift_per_100m_m"] = std::isfinite(m.drift_per_100m_m) ? nlohmann::json(m.drift_per_100m_m)
                                                            : nlohmann::json(nullptr);
  j["drift_percent"] = std::isfinite(m.drift_percent) ? nlohmann::json(m.drift_percent)
                                                      : nlohmann::json(nullptr);
  return j;
}

std::string DescribeDataset(const io::Dataset& d) {
  size_t slot_observations = 0, tag_observations = 0;
  for (const auto& f : d.log.slot_frames) slot_observations += f.slots.size();
  for (const auto& f : d.log.tag_frames) tag_observations += f.tags.size();
  const double duration_s =
      d.groundtruth_trajectory.empty()
          ? 0.0
          : ToSeconds(d.groundtruth_trajectory.back().t_ns - d.groundtruth_trajectory.front().t_ns);
  char text[512];
  std::snprintf(text, sizeof text,
                "%s: %.1f s, %.1f m driven; %zu wheel, %zu steering, %zu IMU samples; "
                "%zu slot frames (%zu slots), %zu tag frames (%zu tags)",
                d.name.c_str(), duration_s, PathLength(d.groundtruth_trajectory),
                d.log.wheel_speeds.size(), d.log.steering_angles.size(),
                d.log.imu_samples.size(), d.log.slot_frames.size(), slot_observations,
                d.log.tag_frames.size(), tag_observations);
  return text;
}

}  // namespace parkslam::app
