#ifndef PARKSLAM_APPS_STEPS_H_
#define PARKSLAM_APPS_STEPS_H_

// The steps the subcommands share (demo runs them one after the other).

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "parkslam/eval/consistency.h"
#include "parkslam/eval/map_metrics.h"
#include "parkslam/eval/trajectory_metrics.h"
#include "parkslam/harness/dead_reckoning.h"
#include "parkslam/harness/fault_injection.h"
#include "parkslam/harness/sensor_stream.h"
#include "parkslam/harness/trace_following.h"
#include "parkslam/io/dataset.h"
#include "parkslam/io/numeric_csv.h"
#include "parkslam/localization/localization_run.h"
#include "parkslam/localization/localizer.h"
#include "parkslam/mapping/mapper.h"
#include "parkslam/perception/front_end.h"

namespace parkslam::app {

// Simulates the scenario and packs the result as a dataset with ground truth.
io::Dataset SimulateDataset(const sim::ScenarioConfig& scenario, std::uint64_t seed);

// Dead reckoning over a dataset with the EKF tuned from its sensor spec.
harness::DeadReckoningResult RunOdometry(const io::Dataset& dataset,
                                         const harness::DeadReckoningOptions& options);

nlohmann::json MetricsToJson(const eval::TrajectoryMetrics& metrics);

// The time a dataset's log spans, to draw progress through its stream in
// tenths of a second: on pixels the stream's events are not the log's, so
// counting them gives no fixed total.
struct DriveSpan {
  TimeNs start_ns = 0, end_ns = 0;
  int TotalTenths() const;
  // Tenths of a second from the start to t_ns, within [0, TotalTenths()].
  int Tenths(TimeNs t_ns) const;
};
DriveSpan SpanOf(const SensorLog& log);

// Runs the mapper over a dataset's stream (harness/sensor_stream.h), tuned
// from its sensor spec; with a progress bar on stderr when `progress`.
// *faults_seen (when given) gets what the stream injected and what the
// dead reckoning saw of it. after_event (when given) sees the mapper after
// every event, before Finish: the map as it stands along the drive.
using MapperWatch = std::function<void(const mapping::Mapper&, TimeNs)>;
mapping::Mapper BuildMap(const io::Dataset& dataset, const mapping::MapperOptions& options,
                         std::optional<SE2> initial_pose, bool progress,
                         const harness::StreamOptions& stream = {},
                         std::string* faults_seen = nullptr, const MapperWatch& after_event = {});

// What the dead reckoning saw of its inputs' faults, one line; "" when
// nothing (no late event, no gated sample, no sensor gap over 0.5 s).
std::string DescribeOdometryFaults(const odometry::OdometryEkfStats& stats);
std::string DescribeMapping(const mapping::Mapper& mapper, double total_s);

// Which truth slots the car passed: detected at least min_sightings times
// according to the dataset's slot labels. Empty when it has no labels.
std::vector<bool> PassedSlots(const io::Dataset& dataset, size_t truth_slots, int min_sightings);
nlohmann::json MapMetricsToJson(const eval::MapMetrics& metrics);
std::string DescribeMapMetrics(const eval::MapMetrics& metrics);

nlohmann::json TraceFollowingToJson(const harness::TraceFollowingResult& result,
                                    const harness::TraceFollowingOptions& options);

// What became of each landmark class's observations in a localization run,
// and how often slots served where a map slot was near: one line a class
// ("slots: 9120 observed, 8800 used, 250 rejected (gate 200, no map slot
// near 50), 70 while lost") and the slot coverage; as JSON for
// metrics.json ("landmarks").
std::string DescribeLandmarkUse(const localization::LocalizationRun& run,
                                const localization::SlotCoverage& coverage);
nlohmann::json LandmarkUseToJson(const localization::LocalizationRun& run,
                                 const localization::SlotCoverage& coverage);

// What a drive taught the localizer of the wheel (docs/localization.md,
// "The wheel's scale"): "wheel speed reads +0.23 % (sigma 0.04 %), as the
// landmarks measure it"; empty where the scale is not estimated.
std::string DescribeWheelScale(const localization::Localizer& localizer);

// The localizer's estimate at each camera frame in the lot's frame
// (T_world_map), beside the truth, as localization.csv holds it
// (docs/report.md); one row a frame (RunLocalization merges a frame's
// slots and tags); frames outside the truth's time span are left out.
io::NumericTable LocalizationLog(const std::vector<localization::LocalizationEstimate>& estimates,
                                 const SE2& T_world_map, const Trajectory& truth);

// The NEES (x, y, yaw) of the tracked estimates against the truth, in the
// lot's frame (T_world_map), as eval::SummarizeNees sums it up; the
// localizer's consistency (docs/localization.md, "Consistency").
eval::NeesSummary LocalizationNees(const std::vector<localization::LocalizationEstimate>& estimates,
                                   const SE2& T_world_map, const Trajectory& truth);
nlohmann::json NeesToJson(const eval::NeesSummary& nees);
std::string DescribeNees(const eval::NeesSummary& nees);

// The camera frames from the first one with a slot's entrance corner within
// radius_m of the car (by the truth) on, and how many of them the localizer
// tracked: a global start cannot fix the pose where no landmark is (an
// entrance corridor without tags), so this is the share it should keep.
struct TrackedFromSlots {
  int frames = 0;
  int tracked = 0;
};
TrackedFromSlots TrackedFromFirstSlot(
    const std::vector<localization::LocalizationEstimate>& estimates, const SemanticMap& truth_map,
    const Trajectory& truth, double radius_m = 5.0);

// Colours of autonomous runs, run i taking kRunColours[i % size] (follow's
// SVG, the report's map and lateral plot).
inline constexpr std::array<const char*, 10> kRunColours = {
    "#d62728", "#1f77b4", "#9467bd", "#ff7f0e", "#8c564b",
    "#e377c2", "#7f7f7f", "#bcbd22", "#17becf", "#393b79"};

// The trace (trace.tum), each run's true path (run_NN.tum) and estimate
// (estimate_NN.tum), and the runs' signed lateral offsets along the trace
// (lateral.csv: s_m, run_NN_m ...; docs/report.md), into `dir`.
void WriteFollowRuns(const std::filesystem::path& dir, const Trajectory& trace_world,
                     const harness::TraceFollowingResult& result);

// A short human-readable summary of a dataset.
std::string DescribeDataset(const io::Dataset& dataset);

}  // namespace parkslam::app

#endif  // PARKSLAM_APPS_STEPS_H_
