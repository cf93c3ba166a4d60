#include <chrono>
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/dataset.h"
#include "parkslam/io/map_json.h"
#include "parkslam/io/tum.h"
#include "parkslam/eval/map_metrics.h"
#include "parkslam/pipeline/odometry_consistency.h"
#include "parkslam/pipeline/trace_following.h"
#include "parkslam/localization/localizer.h"
#include "parkslam/viz/map_svg.h"
#include "progress.h"
#include "steps.h"

namespace parkslam::app {
namespace {

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

void AddDemoCommand(CLI::App& app) {
  struct Options {
    ScenarioOptions scenario;
    std::uint64_t seed = 1;
    std::string out;
    int consistency_runs = 50;
    int follow_runs = 3;
    double follow_speed_kmh = 10.0;
    double live_images_hz = 5.0;
    bool observations = false;
    std::string detector = "classical";
  };
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "demo",
      "The main job on the built-in lot: simulate a drive, dead-reckon it, build the semantic "
      "map, localize a second drive on it, follow the recorded drive autonomously, measure "
      "everything and draw it.");
  cmd->add_option("--out", options->out, "Output folder")->required();
  cmd->add_option("--seed", options->seed, "Random seed")->capture_default_str();
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
  AddDetectorOption(cmd, &options->detector);
  AddScenarioOptions(cmd, &options->scenario);
  cmd->callback([options] {
    const std::filesystem::path out = options->out;
    const double image_rate_hz = options->observations ? 0.0 : options->live_images_hz;
    pipeline::PerceptionOptions perception;
    perception.detector = pipeline::ParseDetectorKind(options->detector);
    const sim::ScenarioConfig scenario = ResolveScenario(options->scenario);
    nlohmann::json metrics;
    const int steps = 7 + (options->consistency_runs > 0) + (options->follow_runs > 0) - 1;
    int step = 0;
    auto header = [&](const char* what) { std::fprintf(stderr, "[%d/%d] %s\n", ++step, steps, what); };

    header("simulating the drive");
    auto t0 = std::chrono::steady_clock::now();
    const io::Dataset dataset = SimulateDataset(scenario, options->seed);
    metrics["simulate_s"] = SecondsSince(t0);
    io::WriteDataset(out / "dataset", dataset);
    std::printf("%s\n", DescribeDataset(dataset).c_str());

    header("dead reckoning (EKF: wheel speed, steering, IMU)");
    t0 = std::chrono::steady_clock::now();
    pipeline::DeadReckoningOptions dr;
    // The car starts at the lot's entrance, a known pose.
    dr.initial_pose = dataset.groundtruth_trajectory.front().T_map_vehicle;
    const pipeline::DeadReckoningResult odometry = RunOdometry(dataset, dr);
    metrics["odometry_s"] = SecondsSince(t0);
    const Trajectory odometry_trajectory = pipeline::ToTrajectory(odometry.poses);
    io::WriteTum(out / "odometry.tum", odometry_trajectory);

    header(image_rate_hz > 0.0
               ? "semantic mapping on pixels (top view, slots, IDs, tags; Max-Mixture back-end)"
               : "semantic mapping (slots, IDs, tags; Max-Mixture back-end)");
    t0 = std::chrono::steady_clock::now();
    const mapping::Mapper mapper = BuildMap(dataset, mapping::MapperOptions{},
                                            dr.initial_pose, true, image_rate_hz, {}, perception);
    metrics["mapping_s"] = SecondsSince(t0);
    const SemanticMap map = mapper.Map();
    const Trajectory mapped_trajectory = mapper.KeyframeTrajectory();
    io::WriteMap(out / "map.json", map);
    io::WriteTum(out / "trajectory.tum", mapped_trajectory);
    std::printf("%s\n", DescribeMapping(mapper, metrics["mapping_s"].get<double>()).c_str());

    header("evaluating");
    const eval::TrajectoryMetrics m =
        eval::EvaluateTrajectory(dataset.groundtruth_trajectory, odometry_trajectory);
    metrics["odometry"] = MetricsToJson(m);
    const eval::TrajectoryMetrics mapped_m =
        eval::EvaluateTrajectory(dataset.groundtruth_trajectory, mapped_trajectory);
    metrics["mapping_trajectory"] = MetricsToJson(mapped_m);
    eval::MapMetricsOptions map_options;
    map_options.truth_slot_mask = PassedSlots(dataset, dataset.groundtruth_map->slots.size(), 3);
    const eval::MapMetrics map_m = eval::EvaluateMap(map, *dataset.groundtruth_map, map_options);
    metrics["map"] = MapMetricsToJson(map_m);
    metrics["dataset"] = dataset.name;
    metrics["detector"] = pipeline::ToString(perception.detector);

    header("localizing a second drive on the map (global start)");
    const io::Dataset second = SimulateDataset(scenario, options->seed + 500);
    io::WriteDataset(out / "second_drive", second);
    const SE2 T_world_map =
        eval::EvaluateMap(map, *dataset.groundtruth_map).T_truth_map;
    localization::Localizer localizer(
        map, localization::LocalizerOptions{},
        pipeline::EkfOptionsFromSensorSpec(scenario.sensors.odometry, scenario.vehicle));
    Trajectory localized;
    {
      DatasetStream stream(second, image_rate_hz, {}, perception);
      SensorSource& source = stream.source();
      while (const auto event = source.Next()) {
        const auto estimate = localizer.Process(*event);
        if (estimate && estimate->state == localization::LocalizerState::kTracking) {
          AppendOrReplaceLast(&localized, {estimate->t_ns, T_world_map * estimate->T_map_vehicle});
        }
      }
    }
    io::WriteTum(out / "second_drive_localized.tum", localized);
    eval::TrajectoryMetricsOptions no_align;
    no_align.align = false;
    const eval::TrajectoryMetrics loc_m =
        eval::EvaluateTrajectory(second.groundtruth_trajectory, localized, no_align);
    metrics["localization"] = MetricsToJson(loc_m);
    metrics["localization"]["frames_tracked"] = static_cast<int>(localized.size());
    std::printf("localization of a second drive: %zu camera frames tracked, RMSE %.3f m, "
                "%.2f deg (in the lot's frame)\n",
                localized.size(), loc_m.ate_rmse_m, loc_m.yaw_rmse_rad * 180.0 / M_PI);

    pipeline::TraceFollowingResult follow;
    if (options->follow_runs > 0) {
      header("following the recorded drive autonomously");
      pipeline::TraceFollowingOptions follow_options;
      follow_options.runs = options->follow_runs;
      follow_options.speed_kmh = options->follow_speed_kmh;
      follow_options.seed = options->seed + 2000;
      follow_options.live_image_rate_hz = image_rate_hz;
      follow_options.perception = perception;
      Progress progress("  runs", options->follow_runs);
      follow = pipeline::FollowTrace(scenario, map, T_world_map.inverse(),
                                     dataset.groundtruth_trajectory, follow_options,
                                     [&progress](int done, int) { progress.Update(done); });
      progress.Finish();
      metrics["trace_following"] = TraceFollowingToJson(follow, follow_options);
      std::printf("trace following, %d runs at %.0f km/h: repeated-trace std %.3f m, lateral "
                  "deviation mean %.3f m, max %.3f m, localization RMSE %.3f m\n",
                  options->follow_runs, options->follow_speed_kmh, follow.metrics.repeat_std_m,
                  follow.metrics.lateral_mean_all_m, follow.metrics.lateral_max_all_m,
                  follow.localization_rmse_m);
    }

    if (options->consistency_runs > 0) {
      header("EKF consistency (NEES over repeated drives)");
      Progress progress("  drives", options->consistency_runs);
      const pipeline::OdometryConsistency c = pipeline::EvaluateOdometryConsistency(
          scenario, options->consistency_runs, options->seed + 1000, 1.0,
          [&progress](int done, int) { progress.Update(done); });
      progress.Finish();
      metrics["odometry_consistency"] = {{"runs", c.runs},
                                         {"mean_anees", c.mean_anees},
                                         {"band_95", {c.band_lower, c.band_upper}},
                                         {"share_inside_band", c.share_inside_band}};
      std::printf("EKF consistency: average NEES %.2f (ideal 3; 95 %% band [%.2f, %.2f]), "
                  "inside the band %.1f %% of the time over %d drives\n",
                  c.mean_anees, c.band_lower, c.band_upper, 100 * c.share_inside_band, c.runs);
    }

    header("drawing");
    viz::MapSvgOptions svg_options;
    svg_options.title = "parkslam demo: the map built from " + dataset.name +
                        " (temporary IDs in orange), with the driven trajectories";
    const std::string svg = viz::RenderMapSvg(
        map,
        {{"ground truth", "#2a9d2a", dataset.groundtruth_trajectory},
         {"dead reckoning (EKF)", "#d62728", odometry_trajectory},
         {"mapper (optimized keyframes)", "#1f77b4", mapped_trajectory}},
        svg_options);
    if (options->follow_runs > 0) {
      std::vector<viz::SvgTrajectory> runs{{"recorded drive (the trace)", "#2a9d2a",
                                            dataset.groundtruth_trajectory}};
      for (size_t i = 0; i < follow.runs.size(); ++i) {
        runs.push_back({i == 0 ? "autonomous runs (true paths)" : "", "#d62728",
                        Transformed(T_world_map.inverse(), follow.runs[i].truth_world)});
      }
      viz::MapSvgOptions follow_svg;
      char title[200];
      std::snprintf(title, sizeof title,
                    "%d autonomous runs at %.0f km/h on the built map: repeated-trace std %.3f m",
                    options->follow_runs, options->follow_speed_kmh, follow.metrics.repeat_std_m);
      follow_svg.title = title;
      io::WriteFileAtomically(out / "traces.svg", viz::RenderMapSvg(map, runs, follow_svg));
    }
    io::WriteFileAtomically(out / "map.svg", svg);
    io::WriteFileAtomically(out / "metrics.json", metrics.dump(2) + "\n");

    std::printf("dead reckoning over %.0f m: ATE rmse %.2f m, max %.2f m; drift %.2f m per "
                "100 m (%.2f %%)\n",
                m.length_m, m.ate_rmse_m, m.ate_max_m, m.drift_per_100m_m, m.drift_percent);
    std::printf("map: %s\n", DescribeMapMetrics(map_m).c_str());
    std::printf("mapper trajectory: ATE rmse %.3f m\n", mapped_m.ate_rmse_m);
    std::printf("wrote %s/{dataset/, odometry.tum, map.json, trajectory.tum, second_drive/, "
                "second_drive_localized.tum, metrics.json, map.svg, traces.svg}\n",
                out.string().c_str());
  });
}

}  // namespace parkslam::app
