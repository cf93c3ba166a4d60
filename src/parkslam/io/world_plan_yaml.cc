#include "parkslam/io/world_plan_yaml.h"

#include "parkslam/io/atomic_file.h"
#include "parkslam/io/io_error.h"
#include "parkslam/io/visit_yaml.h"
#include "parkslam/io/yaml_util.h"
#include "parkslam/sim/route.h"
#include "parkslam/sim/world.h"

namespace parkslam::io {
namespace {

// A scenario's key path as the plan file spells it: "world.hall" is
// "hall", "world.plan.slots[2]" is "slots[2]", "route.approach_m" is
// "route.waypoints_m".
std::string PlanKey(std::string message) {
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"world.plan.", ""},
                                 {"world.", ""},
                                 {"route.approach_m", "route.waypoints_m"}}) {
    if (message.rfind(from, 0) == 0) return to + message.substr(from.size());
  }
  return message;
}

}  // namespace

std::string PlanToYaml(const PlanFile& plan) {
  std::string out =
      "# parkslam world plan: slots, walls, pillars and tags in the map frame (metres),\n"
      "# and a route as waypoints (docs/world_plan.md).\n";
  PlanFile copy = plan;  // VisitFields() is not const
  visit_yaml::WriteFields(copy, 0, &out);
  return out;
}

PlanFile PlanFromYaml(const std::string& yaml_text, const std::string& source_name) {
  const YAML::Node root = yaml_util::LoadYaml(yaml_text, source_name);
  PlanFile plan;
  if (root.IsNull()) ThrowIoError(source_name, 0, "", "an empty plan");
  const yaml_util::YamlReader reader(source_name, true);
  visit_yaml::ReadValue(reader, root, "", &plan);
  return plan;
}

sim::ScenarioConfig ScenarioFromPlan(const PlanFile& plan, const std::string& source_name) {
  std::string error;
  if (!sim::IsValidPlan(plan.world, plan.hall, "", &error)) {
    ThrowIoError(source_name, 0, "", error);
  }
  sim::ScenarioConfig scenario = sim::DefaultScenario();
  sim::WorldConfig& world = scenario.world;
  world = sim::WorldConfig{};
  world.name = plan.name;
  world.hall = plan.hall;
  world.corridor = false;
  world.tag_count = 0;
  world.plan = plan.world;
  sim::RouteConfig& route = scenario.route;
  route = sim::RouteConfig{};
  route.approach_m = plan.route.waypoints_m;
  route.laps = 0;
  route.cruise_speed_kmh = plan.route.cruise_speed_kmh;
  route.turn_speed_kmh = plan.route.turn_speed_kmh;
  if (!scenario.IsValid(&error)) ThrowIoError(source_name, 0, "", PlanKey(error));
  return scenario;
}

sim::ScenarioConfig LoadPlanFile(const std::filesystem::path& path) {
  return ScenarioFromPlan(PlanFromYaml(ReadTextFile(path, kMaxYamlBytes), path.string()),
                          path.string());
}

PlanFile PlanFromScenario(const sim::ScenarioConfig& scenario) {
  PlanFile plan;
  plan.name = scenario.world.name;
  plan.hall = scenario.world.hall;
  plan.world =
      sim::PlanFromWorld(sim::BuildWorld(scenario.world), sim::FloorRegions(scenario.world));
  plan.route.waypoints_m = sim::RouteWaypoints(scenario.route);
  plan.route.cruise_speed_kmh = scenario.route.cruise_speed_kmh;
  plan.route.turn_speed_kmh = scenario.route.turn_speed_kmh;
  return plan;
}

}  // namespace parkslam::io
