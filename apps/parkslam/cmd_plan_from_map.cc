#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "parkslam/control/trace.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/map_json.h"
#include "parkslam/io/output_guard.h"
#include "parkslam/io/tum.h"
#include "parkslam/io/world_plan_yaml.h"
#include "parkslam/sim/world_plan.h"

namespace parkslam::app {
namespace plan_from_map_command {

// The hall of a plan from a map: the map's bounding box with this margin.
constexpr double kHallMargin_m = 1.0;

// Waypoints every spacing_m along a recorded drive (and its last point).
std::vector<Eigen::Vector2d> WaypointsAlong(const Trajectory& drive, double spacing_m) {
  const control::Trace trace(drive);
  std::vector<Eigen::Vector2d> waypoints;
  for (double s_m = 0.0; s_m < trace.length_m(); s_m += spacing_m) {
    waypoints.push_back(trace.PointAt(s_m));
  }
  waypoints.push_back(trace.PointAt(trace.length_m()));
  return waypoints;
}

}  // namespace plan_from_map_command

void AddPlanFromMapCommand(CLI::App& app) {
  using namespace plan_from_map_command;
  struct Options {
    std::string map, out, route, name;
    double spacing_m = 2.0;
  };
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "plan-from-map",
      "Write a map's slots, tags, pillars and walls as a world plan (docs/world_plan.md), "
      "which simulate --plan drives through");
  cmd->add_option("MAP", options->map, "Map JSON (a ground truth, or a map built by `map`)")
      ->required();
  cmd->add_option("--out", options->out, "Plan YAML to write")->required();
  cmd->add_option("--route", options->route,
                  "TUM trajectory of a drive through the lot: its path becomes the plan's "
                  "route (without it the route is left empty, to be filled in)");
  cmd->add_option("--waypoint-spacing-m", options->spacing_m,
                  "Distance between the waypoints taken along --route")
      ->check(CLI::Range(0.5, 50.0))
      ->capture_default_str();
  cmd->add_option("--name", options->name, "Name of the world (default: the map file's stem)");
  cmd->callback([options] {
    std::vector<io::NamedPath> inputs{{options->map, "MAP"}};
    if (!options->route.empty()) inputs.push_back({options->route, "--route"});
    io::CheckOutputsSpareInputs({{options->out, "--out"}}, inputs);
    const SemanticMap map = io::ReadMap(options->map);
    io::PlanFile plan;
    plan.name =
        options->name.empty() ? std::filesystem::path(options->map).stem().string() : options->name;
    plan.hall = sim::MapBounds(map, kHallMargin_m);
    plan.world = sim::PlanFromMap(map);
    if (!options->route.empty()) {
      plan.route.waypoints_m = WaypointsAlong(io::ReadTum(options->route), options->spacing_m);
    }
    std::string error;
    if (!sim::IsValidPlan(plan.world, plan.hall, "", &error)) {
      throw std::runtime_error(options->map + ": the map makes no valid plan: " + error);
    }
    io::WriteFileAtomically(options->out, io::PlanToYaml(plan));
    std::printf(
        "plan of %zu slots, %zu tags, %zu walls, %zu pillars, %zu waypoints written to %s\n",
        plan.world.slots.size(), plan.world.tags.size(), plan.world.walls.size(),
        plan.world.pillars.size(), plan.route.waypoints_m.size(), options->out.c_str());
    if (plan.route.waypoints_m.empty()) {
      std::printf("its route is empty: give route.waypoints_m before simulating it\n");
    }
  });
}

}  // namespace parkslam::app
