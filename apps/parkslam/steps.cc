#include "steps.h"

#include <algorithm>
#include <cstdio>

#include "commands.h"
#include "parkslam/common/angles.h"
#include "parkslam/sim/simulator.h"
#include "progress.h"

namespace parkslam::app {

io::Dataset SimulateDataset(const sim::ScenarioConfig& scenario, std::uint64_t seed) {
  sim::Simulation simulation = sim::Simulate(scenario, seed);
  io::Dataset dataset;
  dataset.name = scenario.world.name + "-seed" + std::to_string(seed);
  dataset.seed = seed;
  dataset.created_by = std::string("parkslam simulate ") + kVersion;
  io::SetScenario(scenario, &dataset);
  dataset.groundtruth_trajectory = sim::GroundTruthTrajectory(simulation);
  dataset.groundtruth_map = sim::ToSemanticMap(simulation.world);
  dataset.groundtruth_map->metadata["seed"] = std::to_string(seed);
  dataset.log = std::move(simulation.log);
  dataset.slot_labels = std::move(simulation.slot_labels);
  return dataset;
}

harness::DeadReckoningResult RunOdometry(const io::Dataset& dataset,
                                         const harness::DeadReckoningOptions& options) {
  SensorLogSource source(dataset.log);
  return harness::RunDeadReckoning(
      source, odometry::EkfOptionsFromSpec(dataset.odometry_spec, dataset.vehicle), options);
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
  j["drift_percent"] =
      std::isfinite(m.drift_percent) ? nlohmann::json(m.drift_percent) : nlohmann::json(nullptr);
  return j;
}

std::string DescribeOdometryFaults(const odometry::OdometryEkfStats& stats) {
  using S = odometry::OdometryEkfStats;
  std::string parts;
  const auto add = [&parts](const std::string& part) {
    parts += (parts.empty() ? "" : ", ") + part;
  };
  if (stats.late_events > 0) add(std::to_string(stats.late_events) + " late events dropped");
  for (int c = 0; c < S::kChannels; ++c) {
    if (stats.rejected[c] > 0 || stats.resets[c] > 0) {
      add(std::string(S::ChannelName(c)) + " " + std::to_string(stats.rejected[c]) +
          " samples gated out, " + std::to_string(stats.resets[c]) + " level changes taken");
    }
  }
  for (int c : {S::kWheelSpeed, S::kSteering, S::kGyro}) {
    if (stats.longest_gap_s[c] > 0.5) {
      char gap[96];
      std::snprintf(gap, sizeof(gap), "%s silent for up to %.1f s",
                    c == S::kGyro ? "imu" : S::ChannelName(c), stats.longest_gap_s[c]);
      add(gap);
    }
  }
  return parts.empty() ? "" : "odometry faults seen: " + parts;
}

int DriveSpan::TotalTenths() const {
  return static_cast<int>(std::max<TimeNs>(0, end_ns - start_ns) / 100'000'000);
}

int DriveSpan::Tenths(TimeNs t_ns) const {
  return std::clamp(static_cast<int>((t_ns - start_ns) / 100'000'000), 0, TotalTenths());
}

DriveSpan SpanOf(const SensorLog& log) {
  std::optional<DriveSpan> span;
  const auto cover = [&span](const auto& events) {
    if (events.empty()) return;
    const TimeNs first = events.front().t_ns, last = events.back().t_ns;
    if (!span) span = DriveSpan{first, last};
    span->start_ns = std::min(span->start_ns, first);
    span->end_ns = std::max(span->end_ns, last);
  };
  cover(log.wheel_speeds);
  cover(log.steering_angles);
  cover(log.imu_samples);
  cover(log.slot_frames);
  cover(log.tag_frames);
  return span.value_or(DriveSpan{});
}

mapping::Mapper BuildMap(const io::Dataset& dataset, const mapping::MapperOptions& options,
                         std::optional<SE2> initial_pose, bool progress,
                         const harness::StreamOptions& stream_options, std::string* faults_seen,
                         const MapperWatch& after_event) {
  mapping::Mapper mapper(
      options, odometry::EkfOptionsFromSpec(dataset.odometry_spec, dataset.vehicle), initial_pose);
  const DriveSpan span = SpanOf(dataset.log);
  std::optional<Progress> bar;
  if (progress) bar.emplace("  mapping", span.TotalTenths());
  harness::SensorStream stream(dataset, stream_options);
  SensorSource& source = stream.source();
  while (const auto event = source.Next()) {
    mapper.Process(*event);
    if (after_event) after_event(mapper, EventTime(*event));
    if (bar) bar->Update(span.Tenths(EventTime(*event)));
  }
  mapper.Finish();
  if (bar) bar->Finish();
  if (faults_seen != nullptr) {
    *faults_seen = stream.DescribeFaults();
    const std::string odometry = DescribeOdometryFaults(mapper.odometry_stats());
    if (!odometry.empty()) *faults_seen += (faults_seen->empty() ? "" : "\n") + odometry;
  }
  return mapper;
}

std::string DescribeMapping(const mapping::Mapper& mapper, double total_s) {
  const mapping::MapperStats& st = mapper.stats();
  std::vector<double> ms = st.keyframe_update_ms;
  double median = 0.0, p99 = 0.0, worst = 0.0;
  if (!ms.empty()) {
    std::sort(ms.begin(), ms.end());
    median = ms[ms.size() / 2];
    p99 = ms[ms.size() * 99 / 100];
    worst = ms.back();
  }
  const SemanticMap map = mapper.Map();
  char text[512];
  std::snprintf(
      text, sizeof text,
      "%d keyframes, %d slot observations (%d with several candidates), %d tag "
      "observations; %d slots created, %d merged, %d dropped as overlapping, %zu in the map, "
      "%zu tags; keyframe update median %.2f ms, p99 %.2f ms, max %.2f ms; final %.2f s (corner "
      "covariances %.2f s); total %.2f s",
      st.keyframes, st.slot_observations, st.mixture_observations, st.tag_observations,
      st.slots_created, st.slots_merged, st.slots_overlapping, map.slots.size(), map.tags.size(),
      median, p99, worst, st.final_solve_ms / 1000.0, st.covariance_ms / 1000.0, total_s);
  std::string description = text;
  if (st.background_solves > 0) {
    std::vector<double> solve_ms = st.background_solve_ms;
    std::sort(solve_ms.begin(), solve_ms.end());
    std::snprintf(text, sizeof text,
                  "; %d background solves, median %.0f ms, max %.0f ms (waited for %.2f s in all)",
                  st.background_solves, solve_ms[solve_ms.size() / 2], solve_ms.back(),
                  st.background_wait_ms / 1000.0);
    description += text;
  }
  return description;
}

std::vector<bool> PassedSlots(const io::Dataset& dataset, size_t truth_slots, int min_sightings) {
  if (dataset.slot_labels.empty()) return {};
  std::vector<int> sightings(truth_slots, 0);
  for (const auto& frame : dataset.slot_labels) {
    for (int label : frame) {
      if (label >= 0 && static_cast<size_t>(label) < truth_slots) ++sightings[label];
    }
  }
  std::vector<bool> passed(truth_slots);
  for (size_t i = 0; i < truth_slots; ++i) passed[i] = sightings[i] >= min_sightings;
  return passed;
}

nlohmann::json CornerErrorsToJson(const eval::CornerErrors& e) {
  return {{"count", e.count},
          {"rmse_m", e.rmse_m},
          {"max_m", e.max_m},
          {"within_2sigma", e.within_2sigma}};
}

nlohmann::json MapMetricsToJson(const eval::MapMetrics& m) {
  return {{"slot_corner_rmse_m", m.slot_corner_rmse_m},
          {"slot_corner_max_m", m.slot_corner_max_m},
          {"observed_corners", CornerErrorsToJson(m.observed_corners)},
          {"unobserved_corners", CornerErrorsToJson(m.unobserved_corners)},
          {"ids_worn_read", m.ids_worn_read},
          {"slots_true", m.slots_true},
          {"slots_matched", m.slots_matched},
          {"slots_missed", m.slots_missed},
          {"slots_spurious", m.slots_spurious},
          {"slots_duplicate", m.slots_duplicate},
          {"id_accuracy", m.id_accuracy},
          {"temporary_id_share", m.temporary_id_share},
          {"tags_true", m.tags_true},
          {"tags_matched", m.tags_matched},
          {"tag_rmse_m", m.tag_rmse_m},
          {"tags_not_in_truth", m.tags_not_in_truth}};
}

std::string DescribeMapMetrics(const eval::MapMetrics& m) {
  char text[768];
  std::snprintf(text, sizeof text,
                "slots: %d of %d matched (%.1f %%), %d missed, %d spurious, %d duplicate\n"
                "slot corner RMSE %.3f m (max %.3f m): observed corners %.3f m (max %.3f m, "
                "%.1f %% inside 2 sigma, %d), unobserved %.3f m (max %.3f m, %.1f %% inside 2 "
                "sigma, %d)\n"
                "ID accuracy %.1f %% (%d read from worn paint), temporary IDs %.1f %%\n"
                "tags: %d of %d matched, RMSE %.3f m; %d in the map not in the lot",
                m.slots_matched, m.slots_true,
                m.slots_true > 0 ? 100.0 * m.slots_matched / m.slots_true : 0.0, m.slots_missed,
                m.slots_spurious, m.slots_duplicate, m.slot_corner_rmse_m, m.slot_corner_max_m,
                m.observed_corners.rmse_m, m.observed_corners.max_m,
                100.0 * m.observed_corners.within_2sigma, m.observed_corners.count,
                m.unobserved_corners.rmse_m, m.unobserved_corners.max_m,
                100.0 * m.unobserved_corners.within_2sigma, m.unobserved_corners.count,
                100.0 * m.id_accuracy, m.ids_worn_read, 100.0 * m.temporary_id_share,
                m.tags_matched, m.tags_true, m.tag_rmse_m, m.tags_not_in_truth);
  return text;
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
                d.log.wheel_speeds.size(), d.log.steering_angles.size(), d.log.imu_samples.size(),
                d.log.slot_frames.size(), slot_observations, d.log.tag_frames.size(),
                tag_observations);
  return text;
}

namespace {

std::string DescribeUse(const char* name, const char* no_landmark,
                        const localization::LandmarkUse& u) {
  char text[256];
  std::snprintf(text, sizeof text,
                "%s: %d observed, %d associated, %d used, %d rejected (gate %d, %s %d), %d "
                "while lost",
                name, u.observed, u.associated, u.used, u.rejected(), u.rejected_gate, no_landmark,
                u.rejected_no_map_landmark, u.while_lost);
  return text;
}

nlohmann::json UseToJson(const localization::LandmarkUse& u) {
  return {{"observed", u.observed},
          {"associated", u.associated},
          {"used", u.used},
          {"rejected_gate", u.rejected_gate},
          {"rejected_no_map_landmark", u.rejected_no_map_landmark},
          {"while_lost", u.while_lost}};
}

}  // namespace

std::string DescribeWheelScale(const localization::Localizer& localizer) {
  // A sigma of 0: not estimated.
  if (!(localizer.wheel_scale_sigma() > 0.0)) return "";
  char line[160];
  std::snprintf(line, sizeof(line),
                "wheel speed reads %+.2f %% (sigma %.2f %%), as the landmarks measure it",
                100.0 * localizer.wheel_scale_error(), 100.0 * localizer.wheel_scale_sigma());
  return line;
}

std::string DescribeLandmarkUse(const localization::LocalizationRun& run,
                                const localization::SlotCoverage& coverage) {
  char text[160];
  std::snprintf(text, sizeof text,
                "\nslots used in %d of the %d tracked frames with a map slot within 5 m (%.1f %%)",
                coverage.frames_used, coverage.frames_near, 100.0 * coverage.share());
  return "landmarks: " + DescribeUse("slots", "no map slot near", run.slots) + "\n           " +
         DescribeUse("tags", "not in the map", run.tags) + text;
}

nlohmann::json LandmarkUseToJson(const localization::LocalizationRun& run,
                                 const localization::SlotCoverage& coverage) {
  return {{"slots", UseToJson(run.slots)},
          {"tags", UseToJson(run.tags)},
          {"frames_with_map_slot_near", coverage.frames_near},
          {"frames_with_slots_used", coverage.frames_used},
          {"slot_use_share", coverage.share()}};
}

namespace {

// An estimate in the lot's frame: the pose T_world_map * T_map_vehicle and
// its covariance turned by the same rotation (R P R^T on x, y).
struct LotEstimate {
  SE2 T_world_vehicle;
  Eigen::Matrix3d covariance;
};

LotEstimate InLot(const localization::LocalizationEstimate& e, const SE2& T_world_map) {
  Eigen::Matrix3d J = Eigen::Matrix3d::Identity();
  J.topLeftCorner<2, 2>() = T_world_map.rotation();
  return {T_world_map * e.T_map_vehicle, J * e.covariance * J.transpose()};
}

}  // namespace

io::NumericTable LocalizationLog(const std::vector<localization::LocalizationEstimate>& estimates,
                                 const SE2& T_world_map, const Trajectory& truth) {
  io::NumericTable log;
  log.columns = {"t_s",         "x_m",        "y_m",       "yaw_rad",   "state",
                 "slots_seen",  "slots_used", "tags_seen", "tags_used", "rejected",
                 "relocalized", "cov_xx",     "cov_xy",    "cov_xyaw",  "cov_yy",
                 "cov_yyaw",    "cov_yawyaw", "true_x_m",  "true_y_m",  "true_yaw_rad"};
  for (const localization::LocalizationEstimate& e : estimates) {
    const std::optional<SE2> true_pose = PoseAt(truth, e.t_ns);
    if (!true_pose) continue;
    const auto [T, P] = InLot(e, T_world_map);
    log.rows.push_back({ToSeconds(e.t_ns),
                        T.x(),
                        T.y(),
                        T.yaw(),
                        static_cast<double>(static_cast<int>(e.state)),
                        static_cast<double>(e.slots.observed),
                        static_cast<double>(e.slots.used),
                        static_cast<double>(e.tags.observed),
                        static_cast<double>(e.tags.used),
                        static_cast<double>(e.rejected()),
                        e.relocalized ? 1.0 : 0.0,
                        P(0, 0),
                        P(0, 1),
                        P(0, 2),
                        P(1, 1),
                        P(1, 2),
                        P(2, 2),
                        true_pose->x(),
                        true_pose->y(),
                        true_pose->yaw()});
  }
  return log;
}

TrackedFromSlots TrackedFromFirstSlot(
    const std::vector<localization::LocalizationEstimate>& estimates, const SemanticMap& truth_map,
    const Trajectory& truth, double radius_m) {
  TrackedFromSlots result;
  bool started = false;
  for (const localization::LocalizationEstimate& e : estimates) {
    const std::optional<SE2> true_pose = PoseAt(truth, e.t_ns);
    if (!true_pose) continue;
    for (size_t i = 0; i < truth_map.slots.size() && !started; ++i) {
      started = (truth_map.slots[i].corners_map[0] - true_pose->translation()).norm() < radius_m;
    }
    if (!started) continue;
    ++result.frames;
    result.tracked += e.state == localization::LocalizerState::kTracking;
  }
  return result;
}

eval::NeesSummary LocalizationNees(const std::vector<localization::LocalizationEstimate>& estimates,
                                   const SE2& T_world_map, const Trajectory& truth) {
  std::vector<double> nees;
  for (const localization::LocalizationEstimate& e : estimates) {
    if (e.state != localization::LocalizerState::kTracking) continue;
    const std::optional<SE2> true_pose = PoseAt(truth, e.t_ns);
    if (!true_pose) continue;
    const auto [T, P] = InLot(e, T_world_map);
    const Eigen::Vector3d error(T.x() - true_pose->x(), T.y() - true_pose->y(),
                                AngleDiff(T.yaw(), true_pose->yaw()));
    nees.push_back(eval::Nees(error, P));
  }
  return eval::SummarizeNees(std::move(nees), 3);
}

nlohmann::json NeesToJson(const eval::NeesSummary& n) {
  return {{"frames", n.frames},
          {"mean", n.mean},
          {"median", n.median},
          {"mean_band", {n.mean_band.lower, n.mean_band.upper}},
          {"effective_frames", n.effective_frames},
          {"effective_mean_band", {n.effective_mean_band.lower, n.effective_mean_band.upper}},
          {"frame_band", {n.frame_band.lower, n.frame_band.upper}},
          {"share_inside_frame_band", n.share_inside_frame_band}};
}

std::string DescribeNees(const eval::NeesSummary& n) {
  char text[480];
  std::snprintf(text, sizeof text,
                "consistency: NEES mean %.2f (ideal 3; 95 %% band of the mean over %d frames "
                "[%.2f, %.2f], over the %d independent frames they are worth [%.2f, %.2f]), "
                "median %.2f; %.1f %% of frames inside the per-frame band [%.2f, %.2f]",
                n.mean, n.frames, n.mean_band.lower, n.mean_band.upper, n.effective_frames,
                n.effective_mean_band.lower, n.effective_mean_band.upper, n.median,
                100.0 * n.share_inside_frame_band, n.frame_band.lower, n.frame_band.upper);
  return text;
}

}  // namespace parkslam::app
