#ifndef PARKSLAM_APPS_STEPS_H_
#define PARKSLAM_APPS_STEPS_H_

// The steps the subcommands share (demo runs them one after the other).

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "parkslam/eval/trajectory_metrics.h"
#include "parkslam/io/dataset.h"
#include "parkslam/pipeline/dead_reckoning.h"

namespace parkslam::app {

// Simulates the scenario and packs the result as a dataset with ground truth.
io::Dataset SimulateDataset(const sim::ScenarioConfig& scenario, std::uint64_t seed);

// Dead reckoning over a dataset with the EKF tuned from its sensor spec.
pipeline::DeadReckoningResult RunOdometry(const io::Dataset& dataset,
                                          const pipeline::DeadReckoningOptions& options);

nlohmann::json MetricsToJson(const eval::TrajectoryMetrics& metrics);

// A short human-readable summary of a dataset.
std::string DescribeDataset(const io::Dataset& dataset);

}  // namespace parkslam::app

#endif  // PARKSLAM_APPS_STEPS_H_
