#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "commands.h"
#include "parkslam/eval/map_metrics.h"
#include "parkslam/harness/trace_following.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/map_json.h"
#include "parkslam/io/numeric_csv.h"
#include "parkslam/io/output_guard.h"
#include "parkslam/io/tum.h"
#include "parkslam/sim/route.h"
#include "parkslam/sim/simulator.h"
#include "parkslam/viz/map_svg.h"
#include "progress.h"
#include "steps.h"

namespace parkslam::app {
namespace follow_command {

std::string Index(int i) {
  char text[16];
  std::snprintf(text, sizeof text, "%02d", i);
  return text;
}

}  // namespace follow_command

nlohmann::json TraceFollowingToJson(const harness::TraceFollowingResult& r,
                                    const harness::TraceFollowingOptions& o) {
  const eval::TraceFollowingMetrics& m = r.metrics;
  auto number = [](double x) {
    return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
  };
  nlohmann::json j;
  j["runs"] = static_cast<int>(r.runs.size());
  j["speed_kmh"] = o.speed_kmh;
  j["odometry_only"] = o.odometry_only;
  j["actuator_delay_s"] = o.vehicle_dynamics.actuator_delay_s;
  j["speed_lag_s"] = o.vehicle_dynamics.speed_lag_s;
  j["understeer_gradient_rad_per_mps2"] = o.vehicle_dynamics.understeer_gradient_rad_per_mps2;
  j["sideslip_rad_per_mps2"] = o.vehicle_dynamics.sideslip_rad_per_mps2;
  j["repeat_std_m"] = number(m.repeat_std_m);
  j["repeat_std_max_m"] = number(m.repeat_std_max_m);
  j["lateral_mean_m"] = number(m.lateral_mean_all_m);
  j["lateral_max_m"] = number(m.lateral_max_all_m);
  j["localization_rmse_m"] = r.localization_rmse_m;
  j["localization_yaw_rmse_deg"] = r.localization_yaw_rmse_rad * 180.0 / M_PI;
  int finished = 0;
  nlohmann::json per_run = nlohmann::json::array();
  for (size_t i = 0; i < r.runs.size(); ++i) {
    finished += r.runs[i].finished;
    per_run.push_back(
        {{"finished", r.runs[i].finished},
         {"duration_s", r.runs[i].duration_s},
         {"lateral_mean_m", number(i < m.lateral_mean_m.size() ? m.lateral_mean_m[i] : NAN)},
         {"lateral_max_m", number(i < m.lateral_max_m.size() ? m.lateral_max_m[i] : NAN)},
         {"localization_rmse_m", r.runs[i].localization_rmse_m},
         {"lost_frames", r.runs[i].lost_frames},
         {"safety_interventions", r.runs[i].safety_interventions},
         {"stopped_s", r.runs[i].stopped_s}});
  }
  j["runs_finished"] = finished;
  j["per_run"] = per_run;
  return j;
}

void WriteFollowRuns(const std::filesystem::path& dir, const Trajectory& trace_world,
                     const harness::TraceFollowingResult& result) {
  io::WriteTum(dir / "trace.tum", trace_world);
  io::NumericTable lateral;
  lateral.columns = {"s_m"};
  for (size_t i = 0; i < result.runs.size(); ++i) {
    const std::string index = follow_command::Index(static_cast<int>(i));
    io::WriteTum(dir / ("run_" + index + ".tum"), result.runs[i].truth_world);
    if (!result.runs[i].estimate_map.empty()) {
      io::WriteTum(dir / ("estimate_" + index + ".tum"), result.runs[i].estimate_map);
    }
    lateral.columns.push_back("run_" + index + "_m");
  }
  const eval::TraceFollowingMetrics& m = result.metrics;
  for (size_t k = 0; k < m.station_s_m.size(); ++k) {
    std::vector<double> row{m.station_s_m[k]};
    for (const std::vector<double>& run : m.lateral_offset_m) row.push_back(run[k]);
    lateral.rows.push_back(row);
  }
  io::WriteNumericCsv(dir / "lateral.csv", lateral);
}

namespace follow_command {

struct Options {
  ScenarioOptions scenario;
  std::string map, out, trace;
  int runs = 10;
  double speed_kmh = 4.0;
  std::uint64_t seed = 1;
  bool odometry_only = false, json = false;
  double live_images_hz = 0.0;
  std::string detector;  // --detector; empty: the configuration's front_end.detector
  std::string vehicle = "ideal";
  ConfigOptions config;
};

// The map's pose in the simulated lot; fails when the map is not of it.
SE2 AlignOnLot(const SemanticMap& map, const sim::ScenarioConfig& scenario,
               const std::string& map_path) {
  const SemanticMap truth = sim::ToSemanticMap(sim::BuildWorld(scenario.world));
  const eval::MapMetrics alignment = eval::EvaluateMap(map, truth);
  if (alignment.slots_matched < 3) {
    throw std::runtime_error(map_path + ": fewer than 3 slots match the world '" +
                             scenario.world.name + "'; is it a map of this lot?");
  }
  return alignment.T_truth_map;
}

// The trace in the lot's frame: --trace, or the recorded human drive.
Trajectory TraceInLot(const Options& o, const sim::ScenarioConfig& scenario,
                      const SE2& T_world_map) {
  Trajectory trace_world;
  if (o.trace.empty()) {
    const std::vector<sim::VehicleState> drive =
        sim::DriveRoute(scenario.route, scenario.vehicle, o.seed);
    for (const sim::VehicleState& s : drive) trace_world.push_back({s.t_ns, s.T_map_vehicle});
  } else {
    trace_world = Transformed(T_world_map, io::ReadTum(o.trace));
  }
  return trace_world;
}

harness::TraceFollowingOptions FollowOptionsOf(const Options& o) {
  const AlgorithmOptions config = o.config.Load();
  harness::TraceFollowingOptions follow;
  follow.perception = config.front_end;
  follow.localizer = config.localizer;
  follow.follower = config.follower;
  follow.runs = o.runs;
  follow.speed_kmh = o.speed_kmh;
  follow.seed = o.seed;
  follow.odometry_only = o.odometry_only;
  if (o.live_images_hz > 0.0) follow.frames = harness::FromLiveRendering{o.live_images_hz};
  if (!o.detector.empty()) follow.perception.detector = perception::ParseDetectorKind(o.detector);
  if (o.vehicle == "realistic") follow.vehicle_dynamics = sim::RealisticDynamics();
  return follow;
}

// traces.svg: the trace and the runs' true paths on the map.
void DrawRuns(const Options& o, const SemanticMap& map, const SE2& T_map_world,
              const Trajectory& trace_world, const harness::TraceFollowingResult& result) {
  const std::filesystem::path out = o.out;
  std::vector<viz::SvgTrajectory> drawn{
      {"trace", "#2a9d2a", Transformed(T_map_world, trace_world)}};
  for (size_t i = 0; i < result.runs.size(); ++i) {
    drawn.push_back({i == 0 ? "autonomous runs (true)" : "", kRunColours[i % kRunColours.size()],
                     Transformed(T_map_world, result.runs[i].truth_world)});
  }
  viz::MapSvgOptions svg;
  char title[256];
  std::snprintf(title, sizeof title,
                "%d autonomous runs at %.0f km/h, %s%s: repeated-trace std %.3f m", o.runs,
                o.speed_kmh, o.vehicle == "realistic" ? "realistic vehicle, " : "",
                o.odometry_only ? "dead reckoning only" : "localized on the map",
                result.metrics.repeat_std_m);
  svg.title = title;
  io::WriteFileAtomically(out / "traces.svg", viz::RenderMapSvg(map, drawn, svg));
}

void Run(const Options& o) {
  std::vector<io::NamedPath> inputs{{o.map, "--map"}, {o.trace, "--trace"}};
  for (const io::NamedPath& file : ScenarioFiles(o.scenario)) inputs.push_back(file);
  io::CheckOutputsSpareInputs({{o.out, "--out", true}}, inputs);
  const std::filesystem::path out = o.out;
  const sim::ScenarioConfig scenario = ResolveScenario(o.scenario);
  const SemanticMap map = io::ReadMap(o.map);
  // The map may live in its own frame: align it onto the simulated lot.
  const SE2 T_world_map = AlignOnLot(map, scenario, o.map);
  const SE2 T_map_world = T_world_map.inverse();
  const Trajectory trace_world = TraceInLot(o, scenario, T_world_map);

  const harness::TraceFollowingOptions follow = FollowOptionsOf(o);
  Progress progress("  runs", o.runs);
  const harness::TraceFollowingResult result =
      harness::FollowTrace(scenario, map, T_map_world, trace_world, follow,
                           [&progress](int done, int) { progress.Update(done); });
  progress.Finish();

  WriteFollowRuns(out, trace_world, result);
  DrawRuns(o, map, T_map_world, trace_world, result);
  nlohmann::json j = TraceFollowingToJson(result, follow);
  // Where the map was, for `parkslam report` of this folder.
  j["map"] = std::filesystem::absolute(o.map).string();
  io::WriteFileAtomically(out / "metrics.json", j.dump(2) + "\n");
  if (o.json) {
    std::cout << j.dump() << "\n";
    return;
  }
  std::printf(
      "%d of %zu runs finished; lateral deviation from the trace: mean %.3f m, max "
      "%.3f m; repeated-trace std %.3f m (max %.3f m); localization RMSE %.3f m, "
      "%.2f deg\n",
      j["runs_finished"].get<int>(), result.runs.size(), result.metrics.lateral_mean_all_m,
      result.metrics.lateral_max_all_m, result.metrics.repeat_std_m,
      result.metrics.repeat_std_max_m, result.localization_rmse_m,
      result.localization_yaw_rmse_rad * 180.0 / M_PI);
  std::printf("wrote %s/{trace.tum, run_*.tum, estimate_*.tum, metrics.json, traces.svg}\n",
              out.string().c_str());
}

}  // namespace follow_command

void AddFollowCommand(CLI::App& app) {
  using namespace follow_command;
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "follow",
      "Closed-loop trace following in the simulator (the paper's IV-B): localize on the map "
      "from sensors simulated at the true pose, steer along the trace, repeat; report the "
      "lateral deviation and the spread of the repeated traces");
  cmd->add_option("--map", options->map, "Map JSON the car localizes on")->required();
  cmd->add_option("--out", options->out, "Output folder")->required();
  cmd->add_option("--runs", options->runs, "Autonomous runs")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  cmd->add_option("--speed-kmh", options->speed_kmh, "Cruise speed")
      ->check(CLI::Range(0.5, 30.0))
      ->capture_default_str();
  cmd->add_option("--seed", options->seed,
                  "Seed of the first run (run r uses seed + r); also "
                  "the seed of the recorded human drive")
      ->check(SeedValidator())
      ->capture_default_str();
  cmd->add_option("--trace", options->trace,
                  "Trace to follow, TUM in the map's frame (default: the recorded human drive "
                  "of the world)");
  cmd->add_flag("--odometry-only", options->odometry_only,
                "Steer from dead reckoning alone (the baseline)");
  cmd->add_flag("--json", options->json, "Print one JSON object");
  cmd->add_option("--live-images", options->live_images_hz,
                  "Run on pixels: render the cameras on the fly at this rate (Hz) from the true "
                  "pose, writing nothing, and localize on what the front end finds in them")
      ->check(CLI::Range(0.0, 30.0));
  AddDetectorOption(cmd, &options->detector);
  AddConfigOptions(cmd, &options->config);
  cmd->add_option("--vehicle", options->vehicle,
                  "The car between commands and road: ideal (a kinematic bicycle that obeys at "
                  "once) or realistic (0.15 s actuator delay, 0.5 s speed lag, tyre slip in "
                  "turns; docs/localization.md)")
      ->check(CLI::IsMember({"ideal", "realistic"}))
      ->capture_default_str();
  AddScenarioOptions(cmd, &options->scenario);
  cmd->callback([options] { Run(*options); });
}

}  // namespace parkslam::app
