#ifndef PARKSLAM_IO_DATASET_H_
#define PARKSLAM_IO_DATASET_H_

// A recorded drive on disk (a folder):
//
//   dataset.yaml                   format "parkslam-dataset", version 2, name,
//                                  seed, created_by, duration_s, counts per
//                                  file, the vehicle, the odometry sensors'
//                                  specification, and for simulated data the
//                                  scenario it was made with. Written last:
//                                  it marks a complete dataset.
//   sensors/wheel_speed.csv        t_ns,speed_mps
//   sensors/steering.csv           t_ns,steering_wheel_rad
//   sensors/imu.csv                t_ns,yaw_rate_radps,heading_rad
//   observations/slots.jsonl       one slot frame a line:
//     {"t_ns": 100000000, "slots": [{"corners": [[x, y] x4], "observed":
//      [true, true, false, false], "sigma_m": 0.05, "confidence": 0.9,
//      "id": [[["3", 0.8], ["8", 0.15]], []]}]}
//     (vehicle frame; "id" holds per digit its [digit, probability]
//     hypotheses, [] for an unread digit; "id": [] when nothing was read)
//   observations/tags.jsonl        one tag frame a line:
//     {"t_ns": ..., "tags": [{"id": 7, "x_m": 5.1, "y_m": -0.4, "range_m": 5.1,
//      "bearing_rad": -0.1, "yaw_rad": 3.1, "cov": [xx, xy, yy],
//      "yaw_sigma_rad": 0.03}]}
//   groundtruth/trajectory.tum     the vehicle's true poses (TUM, io/tum.h)
//   groundtruth/map.json           the true map (io/map_json.h)
//   groundtruth/slot_labels.jsonl  per slot frame: {"t_ns": ..., "slots": [3, -1]},
//                                  the true slot of each observation, -1 false
//
// Ground-truth files are optional. Timestamps strictly increase within every
// file; numbers are written to read back exactly.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "parkslam/common/trajectory.h"
#include "parkslam/map/semantic_map.h"
#include "parkslam/sensor/sensor_log.h"
#include "parkslam/sim/scenario_config.h"
#include "parkslam/sim/simulator.h"

namespace parkslam::io {

inline constexpr char kDatasetFormatName[] = "parkslam-dataset";
// Version 1 held the vehicle and the sensors only inside the scenario; it is
// still read.
inline constexpr int kDatasetFormatVersion = 2;
inline constexpr char kDatasetManifestFile[] = "dataset.yaml";

struct Dataset {
  std::string name;  // "default-seed1"
  std::uint64_t seed = 0;
  std::string created_by;  // "parkslam simulate 0.1.0"
  // What the estimators know of the car and its sensors, as from a
  // datasheet: dataset.yaml's vehicle and sensors.odometry.
  VehicleParameters vehicle;
  OdometrySensorSpec odometry_spec;
  // Simulated data only: the world, route, vehicle and sensor configuration
  // it was made with (its vehicle and odometry are the two above). A
  // recording from a real car has none.
  std::optional<sim::ScenarioConfig> scenario;
  SensorLog log;
  Trajectory groundtruth_trajectory;           // empty when absent
  std::optional<SemanticMap> groundtruth_map;  // absent when no ground truth
  // Empty when absent; else one vector per slot frame of the log.
  sim::SlotObservationLabels slot_labels;
};

// A simulated dataset's header: the scenario, and the vehicle and odometry
// specification taken from it.
void SetScenario(const sim::ScenarioConfig& scenario, Dataset* dataset);

// Writes every file atomically, dataset.yaml last (after removing an old
// one), and removes ground-truth files of an earlier dataset in `dir` that
// this one lacks. Throws IoError, naming the file, for data that would not
// read back: non-finite numbers, timestamps not strictly increasing, labels
// that do not match the slot frames.
void WriteDataset(const std::filesystem::path& dir, const Dataset& dataset);

// Reads and checks a dataset: exact CSV headers, finite numbers, strictly
// increasing t_ns in every file, well-formed JSON lines with known keys only,
// counts as announced in dataset.yaml, labels matching the slot frames.
// Throws IoError naming the file, the line and the field.
Dataset ReadDataset(const std::filesystem::path& dir);

// What `parkslam check-dataset` reports before a long run: each stream's
// extent, rate and longest gap, and every problem found, not only the
// first (docs/dataset_format.md, "Checking a dataset").
struct StreamSummary {
  std::string name;  // the file, or "images/index.csv (front)"
  std::size_t count = 0;
  double first_s = 0.0, last_s = 0.0;
  double median_period_s = 0.0;  // 0 with fewer than two samples
  double max_gap_s = 0.0, max_gap_after_s = 0.0;
};
struct DatasetCheck {
  std::vector<StreamSummary> streams;
  std::vector<std::string> errors;  // each names its file (and line and field where it has them)
  bool ok() const { return errors.empty(); }
};

// Reads every file of a dataset on its own, as ReadDataset does, and adds
// what a reader of one file cannot see: a gap longer than max_gap_s (or
// 1.5 times a slower stream's own period) in any stream (sensors,
// observation frames, each camera's images), counts that
// differ from dataset.yaml, images whose size (from their header) is not
// their camera's in images/rig.yaml. Throws nothing for a bad dataset.
DatasetCheck CheckDataset(const std::filesystem::path& dir, double max_gap_s = 1.0);

}  // namespace parkslam::io

#endif  // PARKSLAM_IO_DATASET_H_
