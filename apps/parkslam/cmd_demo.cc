#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "commands.h"
#include "detection_scoring.h"
#include "interruption.h"
#include "parkslam/eval/map_metrics.h"
#include "parkslam/harness/odometry_consistency.h"
#include "parkslam/harness/trace_following.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/dataset.h"
#include "parkslam/io/map_json.h"
#include "parkslam/io/numeric_csv.h"
#include "parkslam/io/tum.h"
#include "parkslam/localization/localization_run.h"
#include "parkslam/localization/localizer.h"
#include "parkslam/viz/map_svg.h"
#include "progress.h"
#include "steps.h"

namespace parkslam::app {
namespace demo_command {

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A handful of top views of the mapping drive through the front end,
// scored against the truth: the perception part of the report
// (perception/*.jpg and metrics "perception").
nlohmann::json PerceptionSamples(const sim::ScenarioConfig& scenario, std::uint64_t seed,
                                 const perception::PerceptionOptions& perception, int frames,
                                 const std::filesystem::path& dir) {
  const DriveScorer drive(scenario, seed, perception);
  const Trajectory& truth = drive.truth();
  Scores scores;
  struct Sample {
    double t_s = 0.0;
    ImageScore score;
    cv::Mat overlay;
  };
  std::vector<Sample> samples;
  const TimeNs span = truth.back().t_ns - truth.front().t_ns;
  Progress progress("  frames", frames);
  for (int k = 0; k < frames; ++k) {
    const TimeNs t = truth.front().t_ns + span * (2 * k + 1) / (2 * frames);
    const DriveScorer::Frame frame = drive.ScoreAt(t, &scores);
    samples.push_back({ToSeconds(t - truth.front().t_ns), frame.score,
                       Overlay(frame.out.top_view, frame.truth_points, frame.out.detection,
                               frame.truth_entrances)});
    progress.Update(k + 1);
  }
  progress.Finish();
  // Best: most slots right with no error; worst: most errors; missed: the
  // frame that misses the most slots.
  nlohmann::json pictures = nlohmann::json::array();
  const auto pick = [&](const char* name, const char* caption, auto better) {
    if (samples.empty()) return;
    const auto it = std::max_element(samples.begin(), samples.end(), better);
    std::filesystem::create_directories(dir);
    std::vector<std::uint8_t> bytes;
    cv::imencode(".jpg", it->overlay, bytes, {cv::IMWRITE_JPEG_QUALITY, 80});
    io::WriteFileAtomically(
        dir / (std::string(name) + ".jpg"),
        std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
    pictures.push_back(
        {{"file", std::string("perception/") + name + ".jpg"},
         {"caption", caption},
         {"t_s", it->t_s},
         {"slots_true_positives", it->score.slots.true_positives},
         {"slots_false_positives", it->score.slots.false_positives},
         {"slots_false_negatives", it->score.slots.false_negatives},
         {"marking_points_false_positives", it->score.marking_points.false_positives},
         {"marking_points_false_negatives", it->score.marking_points.false_negatives}});
  };
  pick("best", "the frame with the most slots found and no error",
       [&](const Sample& a, const Sample& b) {
         return std::make_pair(-a.score.errors(), a.score.slots.true_positives) <
                std::make_pair(-b.score.errors(), b.score.slots.true_positives);
       });
  pick("worst", "the frame with the most errors (false and missed points and slots)",
       [&](const Sample& a, const Sample& b) { return a.score.errors() < b.score.errors(); });
  pick("missed", "the frame that misses the most slots", [&](const Sample& a, const Sample& b) {
    return a.score.slots.false_negatives < b.score.slots.false_negatives;
  });
  nlohmann::json j = ToJson(scores);
  j.erase("time_ms_median");
  j.erase("time_ms_max_frame");
  j["pictures"] = pictures;
  return j;
}

struct Options {
  ScenarioOptions scenario;
  std::uint64_t seed = 1;
  std::string out;
  int consistency_runs = 50;
  int follow_runs = 3;
  double follow_speed_kmh = 10.0;
  double live_images_hz = 5.0;
  bool observations = false;
  std::string detector;  // --detector; empty: the configuration's front_end.detector
  int perception_frames = 24;
  bool no_report = false;
  std::string start = "global";  // the second drive's: global or entrance
  ConfigOptions config;
};

// The EKF on the drive's wheel speed, steering and IMU, from the known
// start pose; writes odometry.tum.
Trajectory DeadReckon(const io::Dataset& dataset, const SE2& initial_pose,
                      const std::filesystem::path& out, nlohmann::json* metrics) {
  const auto t0 = std::chrono::steady_clock::now();
  harness::DeadReckoningOptions dr;
  dr.initial_pose = initial_pose;
  const harness::DeadReckoningResult odometry = RunOdometry(dataset, dr);
  (*metrics)["odometry_s"] = SecondsSince(t0);
  const Trajectory odometry_trajectory = harness::ToTrajectory(odometry.poses);
  io::WriteTum(out / "odometry.tum", odometry_trajectory);
  return odometry_trajectory;
}

// The semantic map of the drive: writes map.json and trajectory.tum;
// returns the optimized keyframe trajectory.
Trajectory MapDrive(const io::Dataset& dataset, const AlgorithmOptions& config,
                    const SE2& initial_pose, const harness::FrameSource& frames,
                    const perception::PerceptionOptions& perception,
                    const std::filesystem::path& out, nlohmann::json* metrics) {
  const auto t0 = std::chrono::steady_clock::now();
  const mapping::Mapper mapper =
      BuildMap(dataset, config.mapper, initial_pose, true, {frames, perception, {}});
  (*metrics)["mapping_s"] = SecondsSince(t0);
  const Trajectory mapped_trajectory = mapper.KeyframeTrajectory();
  io::WriteMap(out / "map.json", mapper.Map());
  io::WriteTum(out / "trajectory.tum", mapped_trajectory);
  std::printf("%s\n", DescribeMapping(mapper, (*metrics)["mapping_s"].get<double>()).c_str());
  return mapped_trajectory;
}

struct Evaluation {
  eval::TrajectoryMetrics odometry, mapped;
  eval::MapMetrics map;
  SemanticMap truth_map;  // as written beside the drive
};

Evaluation Evaluate(const io::Dataset& dataset, const Trajectory& odometry_trajectory,
                    const Trajectory& mapped_trajectory, const SemanticMap& map,
                    const perception::PerceptionOptions& perception,
                    const std::filesystem::path& out, nlohmann::json* metrics_out) {
  nlohmann::json& metrics = *metrics_out;
  Evaluation e;
  e.odometry = eval::EvaluateTrajectory(dataset.groundtruth_trajectory, odometry_trajectory);
  metrics["odometry"] = MetricsToJson(e.odometry);
  e.mapped = eval::EvaluateTrajectory(dataset.groundtruth_trajectory, mapped_trajectory);
  metrics["mapping_trajectory"] = MetricsToJson(e.mapped);
  eval::MapMetricsOptions map_options;
  map_options.truth_slot_mask = PassedSlots(dataset, dataset.groundtruth_map->slots.size(), 3);
  // The truth as written beside the drive (millimetres), as `eval-map` and
  // the report read it.
  e.truth_map = io::ReadMap(out / "dataset" / "groundtruth" / "map.json");
  e.map = eval::EvaluateMap(map, e.truth_map, map_options);
  metrics["map"] = MapMetricsToJson(e.map);
  metrics["dataset"] = dataset.name;
  metrics["command"] = CommandLine();
  metrics["version"] = kVersion;
  metrics["detector"] = perception::ToString(perception.detector);
  return e;
}

// A second drive (seed + 500) localized on the map from a global start, or
// from the map's entrance (where its drive began, and the second drive
// begins: the route's start); writes second_drive/,
// second_drive_localized.tum and localization.csv.
// Returns the map's pose in the lot (from the truth).
SE2 LocalizeSecondDrive(const Options& o, const sim::ScenarioConfig& scenario,
                        const AlgorithmOptions& config, const SemanticMap& map,
                        const SemanticMap& truth_map, const harness::FrameSource& frames,
                        const perception::PerceptionOptions& perception, nlohmann::json* metrics) {
  const std::filesystem::path out = o.out;
  const io::Dataset second = SimulateDataset(scenario, o.seed + 500);
  io::WriteDataset(out / "second_drive", second);
  const SE2 T_world_map = eval::EvaluateMap(map, truth_map).T_truth_map;
  localization::Localizer localizer(
      map, config.localizer,
      odometry::EkfOptionsFromSpec(scenario.sensors.odometry, scenario.vehicle));
  if (o.start == "entrance") {
    // As `localize --init entrance`.
    localizer.SetPose(io::ParseStartPose("entrance", map, "--start", "the map"),
                      config.localizer.EntranceSigmas().cwiseAbs2().asDiagonal());
  }
  (*metrics)["localization"]["start"] = o.start;
  localization::LocalizationRun run;
  {
    harness::SensorStream stream(second, {frames, perception, {}});
    stream.SearchTagsFor(localizer);
    run = localization::RunLocalization(stream.source(), &localizer);
  }
  const std::vector<localization::LocalizationEstimate>& estimates = run.estimates;
  const Trajectory localized = Transformed(T_world_map, run.tracked);
  io::WriteTum(out / "second_drive_localized.tum", localized);
  io::WriteNumericCsv(out / "localization.csv",
                      LocalizationLog(estimates, T_world_map, second.groundtruth_trajectory));
  eval::TrajectoryMetricsOptions no_align;
  no_align.align = false;
  const eval::TrajectoryMetrics loc_m =
      eval::EvaluateTrajectory(second.groundtruth_trajectory, localized, no_align);
  (*metrics)["localization"] = MetricsToJson(loc_m);
  (*metrics)["localization"]["frames_tracked"] = static_cast<int>(localized.size());
  (*metrics)["localization"]["frames"] = run.frames;
  const TrackedFromSlots from_slots =
      TrackedFromFirstSlot(estimates, truth_map, second.groundtruth_trajectory);
  (*metrics)["localization"]["from_first_slot"] = {{"frames", from_slots.frames},
                                                   {"tracked", from_slots.tracked}};
  const localization::SlotCoverage coverage = localization::MeasureSlotCoverage(estimates, map);
  (*metrics)["localization"]["landmarks"] = LandmarkUseToJson(run, coverage);
  const eval::NeesSummary nees =
      LocalizationNees(estimates, T_world_map, second.groundtruth_trajectory);
  (*metrics)["localization"]["nees"] = NeesToJson(nees);
  std::printf(
      "localization of a second drive: %zu of %d camera frames tracked (%.1f %%; %.1f %% from "
      "the first with a slot within 5 m on), RMSE %.3f m, %.2f deg (in the lot's frame)\n%s\n"
      "%s\n",
      localized.size(), run.frames,
      100.0 * static_cast<double>(localized.size()) / std::max(run.frames, 1),
      100.0 * from_slots.tracked / std::max(from_slots.frames, 1), loc_m.ate_rmse_m,
      loc_m.yaw_rmse_rad * 180.0 / M_PI, DescribeLandmarkUse(run, coverage).c_str(),
      DescribeNees(nees).c_str());
  const std::string wheel = DescribeWheelScale(localizer);
  if (!wheel.empty()) {
    std::printf("%s\n", wheel.c_str());
    (*metrics)["localization"]["wheel_scale_error"] = localizer.wheel_scale_error();
    (*metrics)["localization"]["wheel_scale_sigma"] = localizer.wheel_scale_sigma();
  }
  return T_world_map;
}

// Autonomous runs along the recorded drive (seed + 2000) on the map;
// writes follow/.
harness::TraceFollowingResult FollowRecordedDrive(
    const Options& o, const sim::ScenarioConfig& scenario, const AlgorithmOptions& config,
    const SemanticMap& map, const SE2& T_world_map, const io::Dataset& dataset,
    const harness::FrameSource& frames, const perception::PerceptionOptions& perception,
    nlohmann::json* metrics) {
  const std::filesystem::path out = o.out;
  harness::TraceFollowingOptions follow_options;
  follow_options.runs = o.follow_runs;
  follow_options.speed_kmh = o.follow_speed_kmh;
  follow_options.seed = o.seed + 2000;
  follow_options.frames = frames;
  follow_options.perception = perception;
  follow_options.localizer = config.localizer;
  follow_options.follower = config.follower;
  Progress progress("  runs", o.follow_runs);
  const harness::TraceFollowingResult follow =
      harness::FollowTrace(scenario, map, T_world_map.inverse(), dataset.groundtruth_trajectory,
                           follow_options, [&progress](int done, int) { progress.Update(done); });
  progress.Finish();
  (*metrics)["trace_following"] = TraceFollowingToJson(follow, follow_options);
  // The runs and their lateral offsets along the trace, for the report.
  std::filesystem::create_directories(out / "follow");
  WriteFollowRuns(out / "follow", dataset.groundtruth_trajectory, follow);
  std::printf(
      "trace following, %d runs at %.0f km/h: repeated-trace std %.3f m, lateral "
      "deviation mean %.3f m, max %.3f m, localization RMSE %.3f m\n",
      o.follow_runs, o.follow_speed_kmh, follow.metrics.repeat_std_m,
      follow.metrics.lateral_mean_all_m, follow.metrics.lateral_max_all_m,
      follow.localization_rmse_m);
  return follow;
}

// NEES of the dead-reckoning EKF over repeated drives (seed + 1000);
// writes ekf_nees.csv.
void EkfConsistency(const Options& o, const sim::ScenarioConfig& scenario,
                    nlohmann::json* metrics) {
  const std::filesystem::path out = o.out;
  Progress progress("  drives", o.consistency_runs);
  const harness::OdometryConsistency c =
      harness::EvaluateOdometryConsistency(scenario, o.consistency_runs, o.seed + 1000, 1.0,
                                           [&progress](int done, int) { progress.Update(done); });
  progress.Finish();
  io::NumericTable nees;
  nees.columns = {"t_s", "anees"};
  for (size_t k = 0; k < c.times_s.size(); ++k) nees.rows.push_back({c.times_s[k], c.anees[k]});
  io::WriteNumericCsv(out / "ekf_nees.csv", nees);
  (*metrics)["odometry_consistency"] = {{"runs", c.runs},
                                        {"mean_anees", c.mean_anees},
                                        {"band_95", {c.band_lower, c.band_upper}},
                                        {"share_inside_band", c.share_inside_band}};
  std::printf(
      "EKF consistency: average NEES %.2f (ideal 3; 95 %% band [%.2f, %.2f]), "
      "inside the band %.1f %% of the time over %d drives\n",
      c.mean_anees, c.band_lower, c.band_upper, 100 * c.share_inside_band, c.runs);
  // What the localizer and the mapper take: the motion over a window
  // (docs/odometry.md, "Motion over a window"), on the same drives.
  Progress window_progress("  windows", o.consistency_runs);
  const std::vector<harness::RelativeOdometryConsistency> by_window =
      harness::EvaluateRelativeOdometryConsistency(
          scenario, o.consistency_runs, o.seed + 1000, {1.0, 5.0}, 0.2,
          [&window_progress](int done, int) { window_progress.Update(done); });
  window_progress.Finish();
  nlohmann::json windows = nlohmann::json::array();
  std::string line = "EKF motion over windows:";
  for (const harness::RelativeOdometryConsistency& w : by_window) {
    windows.push_back({{"window_s", w.window_s},
                       {"windows", w.windows},
                       {"mean_nees", w.mean_nees},
                       {"mean_position_nees", w.mean_position_nees},
                       {"mean_yaw_nees", w.mean_yaw_nees},
                       {"turning_windows", w.turning_windows},
                       {"mean_turning_nees", w.mean_turning_nees},
                       {"share_inside_window_band", w.share_inside_window_band}});
    char part[160];
    std::snprintf(part, sizeof(part), "%s %.0f s NEES %.2f (in turns %.2f), %.1f %% inside",
                  windows.size() > 1 ? ";" : "", w.window_s, w.mean_nees, w.mean_turning_nees,
                  100 * w.share_inside_window_band);
    line.append(part);
  }
  (*metrics)["odometry_consistency"]["windows"] = windows;
  std::printf("%s (ideal 3)\n", line.c_str());
}

// map.svg (the map with the three trajectories) and, after trace
// following, traces.svg.
void DrawMaps(const Options& o, const io::Dataset& dataset, const SemanticMap& map,
              const Trajectory& odometry_trajectory, const Trajectory& mapped_trajectory,
              const SE2& T_world_map, const harness::TraceFollowingResult& follow) {
  const std::filesystem::path out = o.out;
  viz::MapSvgOptions svg_options;
  svg_options.title = "parkslam demo: the map built from " + dataset.name +
                      " (temporary IDs in orange), with the driven trajectories";
  const std::string svg =
      viz::RenderMapSvg(map,
                        {{"ground truth", "#2a9d2a", dataset.groundtruth_trajectory},
                         {"dead reckoning (EKF)", "#d62728", odometry_trajectory},
                         {"mapper (optimized keyframes)", "#1f77b4", mapped_trajectory}},
                        svg_options);
  if (o.follow_runs > 0) {
    std::vector<viz::SvgTrajectory> runs{
        {"recorded drive (the trace)", "#2a9d2a", dataset.groundtruth_trajectory}};
    for (size_t i = 0; i < follow.runs.size(); ++i) {
      runs.push_back({i == 0 ? "autonomous runs (true paths)" : "", "#d62728",
                      Transformed(T_world_map.inverse(), follow.runs[i].truth_world)});
    }
    viz::MapSvgOptions follow_svg;
    char title[200];
    std::snprintf(title, sizeof title,
                  "%d autonomous runs at %.0f km/h on the built map: repeated-trace std %.3f m",
                  o.follow_runs, o.follow_speed_kmh, follow.metrics.repeat_std_m);
    follow_svg.title = title;
    io::WriteFileAtomically(out / "traces.svg", viz::RenderMapSvg(map, runs, follow_svg));
  }
  io::WriteFileAtomically(out / "map.svg", svg);
}

void PrintSummary(const Options& o, const Evaluation& e) {
  const eval::TrajectoryMetrics& m = e.odometry;
  std::printf(
      "dead reckoning over %.0f m: ATE rmse %.2f m, max %.2f m; drift %.2f m per "
      "100 m (%.2f %%)\n",
      m.length_m, m.ate_rmse_m, m.ate_max_m, m.drift_per_100m_m, m.drift_percent);
  std::printf("map: %s\n", DescribeMapMetrics(e.map).c_str());
  std::printf("mapper trajectory: ATE rmse %.3f m\n", e.mapped.ate_rmse_m);
  std::printf(
      "wrote %s/{dataset/, odometry.tum, map.json, trajectory.tum, second_drive/, "
      "second_drive_localized.tum, localization.csv, metrics.json, map.svg, traces.svg, "
      "report.html}\n",
      std::filesystem::path(o.out).string().c_str());
}

// Moves every entry of the finished staging folder into --out, each in one
// rename, replacing an entry of the same name (a former demo's output) and
// leaving everything else in --out as it was.
void MoveInto(const std::filesystem::path& staging, const std::filesystem::path& out) {
  namespace fs = std::filesystem;
  fs::create_directories(out);
  for (const fs::directory_entry& entry : fs::directory_iterator(staging)) {
    const fs::path destination = out / entry.path().filename();
    std::error_code ec;
    if (fs::is_directory(destination, ec) && !fs::is_symlink(destination, ec)) {
      fs::remove_all(destination);
    }
    fs::rename(entry.path(), destination);
  }
}

void Run(const Options& given) {
  // Written into a staging folder beside --out and moved in once whole: an
  // interrupted or failed demo leaves --out as it was (a killed one leaves
  // the staging folder, which the next run's sweep removes).
  std::error_code ec;
  if (std::filesystem::exists(given.out, ec) && !std::filesystem::is_directory(given.out, ec)) {
    throw std::runtime_error("--out " + given.out + ": a file, not a folder");
  }
  io::TemporaryFile staging(StagingTarget(given.out), io::TemporaryFile::Kind::kFolder);
  Options o = given;
  o.out = staging.path().string();
  std::filesystem::create_directories(o.out);
  const InterruptionScope interruption;
  const auto checkpoint = [] { InterruptionScope::ThrowIfInterrupted("--out is as it was"); };
  const std::filesystem::path out = o.out;
  const bool on_pixels = !o.observations && o.live_images_hz > 0.0;
  const harness::FrameSource frames =
      on_pixels ? harness::FrameSource(harness::FromLiveRendering{o.live_images_hz})
                : harness::FrameSource(harness::FromObservations{});
  const AlgorithmOptions config = o.config.Load();
  perception::PerceptionOptions perception = config.front_end;
  if (!o.detector.empty()) perception.detector = perception::ParseDetectorKind(o.detector);
  const sim::ScenarioConfig scenario = ResolveScenario(o.scenario);
  nlohmann::json metrics;
  const int steps = 7 + (o.consistency_runs > 0) + (o.follow_runs > 0) + (o.perception_frames > 0) +
                    !o.no_report - 1;
  int step = 0;
  auto header = [&](const std::string& what) {
    checkpoint();
    std::fprintf(stderr, "[%d/%d] %s\n", ++step, steps, what.c_str());
  };

  header("simulating the drive");
  const auto t0 = std::chrono::steady_clock::now();
  const io::Dataset dataset = SimulateDataset(scenario, o.seed);
  metrics["simulate_s"] = SecondsSince(t0);
  io::WriteDataset(out / "dataset", dataset);
  std::printf("%s\n", DescribeDataset(dataset).c_str());

  header("dead reckoning (EKF: wheel speed, steering, IMU)");
  // The car starts at the lot's entrance, a known pose.
  const SE2 initial_pose = dataset.groundtruth_trajectory.front().T_map_vehicle;
  const Trajectory odometry_trajectory = DeadReckon(dataset, initial_pose, out, &metrics);

  header(on_pixels ? "semantic mapping on pixels (top view, slots, IDs, tags; Max-Mixture back-end)"
                   : "semantic mapping (slots, IDs, tags; Max-Mixture back-end)");
  const Trajectory mapped_trajectory =
      MapDrive(dataset, config, initial_pose, frames, perception, out, &metrics);
  // Everything after uses the map as written (millimetres), as a car
  // would load it, so that the report finds the same figures in the file.
  const SemanticMap map = io::ReadMap(out / "map.json");

  header("evaluating");
  const Evaluation evaluation =
      Evaluate(dataset, odometry_trajectory, mapped_trajectory, map, perception, out, &metrics);

  header("localizing a second drive on the map (" + o.start + " start)");
  const SE2 T_world_map = LocalizeSecondDrive(o, scenario, config, map, evaluation.truth_map,
                                              frames, perception, &metrics);

  harness::TraceFollowingResult follow;
  if (o.follow_runs > 0) {
    header("following the recorded drive autonomously");
    follow = FollowRecordedDrive(o, scenario, config, map, T_world_map, dataset, frames, perception,
                                 &metrics);
  }
  if (o.consistency_runs > 0) {
    header("EKF consistency (NEES over repeated drives)");
    EkfConsistency(o, scenario, &metrics);
  }
  if (o.perception_frames > 0) {
    header("perception on a handful of frames of the mapping drive");
    metrics["perception"] =
        PerceptionSamples(scenario, o.seed, perception, o.perception_frames, out / "perception");
    const nlohmann::json& p = metrics["perception"];
    std::printf("perception on %d frames: slots precision %.1f %%, recall %.1f %%\n",
                p["images"].get<int>(), 100 * p["slots"]["precision"].get<double>(),
                100 * p["slots"]["recall"].get<double>());
  }

  header("drawing");
  DrawMaps(o, dataset, map, odometry_trajectory, mapped_trajectory, T_world_map, follow);
  io::WriteFileAtomically(out / "metrics.json", metrics.dump(2) + "\n");
  if (!o.no_report) {
    header("writing the report");
    WriteReport(out, {}, out / "report.html");
  }
  checkpoint();
  MoveInto(out, given.out);
  PrintSummary(given, evaluation);
}

}  // namespace demo_command

void AddDemoCommand(CLI::App& app) {
  using namespace demo_command;
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "demo",
      "The main job on the built-in lot: simulate a drive, dead-reckon it, build the semantic "
      "map, localize a second drive on it, follow the recorded drive autonomously, measure "
      "everything and draw it.");
  cmd->add_option("--out", options->out, "Output folder")->required();
  cmd->add_option("--seed", options->seed, "Random seed")
      ->check(SeedValidator())
      ->capture_default_str();
  cmd->add_option("--consistency-runs", options->consistency_runs,
                  "Monte-Carlo runs for the EKF consistency (NEES) check; 0 skips it")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  cmd->add_option("--follow-runs", options->follow_runs,
                  "Autonomous runs along the recorded trace; 0 skips trace following")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  cmd->add_option("--follow-speed-kmh", options->follow_speed_kmh, "Speed of the autonomous runs")
      ->check(CLI::Range(0.5, 30.0))
      ->capture_default_str();
  cmd->add_option("--live-images", options->live_images_hz,
                  "Camera frame sets per second: mapping, localization and trace following run "
                  "on pixels (rendered on the fly, fused, slots, IDs and tags detected)")
      ->check(CLI::Range(0.1, 30.0))
      ->capture_default_str();
  cmd->add_flag("--observations", options->observations,
                "Skip the cameras: run on the simulator's observation-level slot and tag "
                "detections instead of pixels (fast)");
  cmd->add_option("--perception-frames", options->perception_frames,
                  "Top views of the mapping drive scored against the truth for the report's "
                  "perception part; 0 skips them")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  cmd->add_flag("--no-report", options->no_report, "Do not write report.html");
  cmd->add_option("--start", options->start,
                  "The second drive's start: global (an unknown pose, localized globally) or "
                  "entrance (the map's entrance, where its drive and the second one begin)")
      ->check(CLI::IsMember({"global", "entrance"}));
  AddDetectorOption(cmd, &options->detector);
  AddConfigOptions(cmd, &options->config);
  AddScenarioOptions(cmd, &options->scenario);
  cmd->callback([options] { Run(*options); });
}

}  // namespace parkslam::app
