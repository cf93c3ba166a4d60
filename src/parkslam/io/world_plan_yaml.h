#ifndef PARKSLAM_IO_WORLD_PLAN_YAML_H_
#define PARKSLAM_IO_WORLD_PLAN_YAML_H_

// World plan files (docs/world_plan.md): a lot given slot by slot, with its
// walls, pillars, tags and a route as waypoints, read as strictly as the
// scenario files (unknown keys and bad values are errors naming the file,
// the line and the key path):
//
//   name: "garage_b2"
//   hall: {min_x_m: 0, min_y_m: 0, max_x_m: 40, max_y_m: 30}
//   floor: [{min_x_m: ...}, ...]        optional; default: the hall
//   slots:
//     - kind: "perpendicular"
//       corners_m: [[8, 5.6], [10.5, 5.6], [10.5, 0.3], [8, 0.3]]
//       painted_id: "01"
//       id_legible: true
//   walls: [{a_m: [0, 0], b_m: [40, 0], normal: [0, 1]}, ...]
//   pillars: [{center_m: [12, 6], half_size_m: 0.3}, ...]
//   tags: [{id: 0, p_m: [3, 0], normal_yaw_deg: 90, size_m: 0.488,
//           mount: "wall", mount_index: 0}, ...]
//   route: {waypoints_m: [[x, y], ...], cruise_speed_kmh: 9, turn_speed_kmh: 4}

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "parkslam/sim/scenario_config.h"
#include "parkslam/sim/world_plan.h"

namespace parkslam::io {

// The drive through a plan: the waypoints in driving order, smoothed and
// driven by the simulator's driver (sim/route.h) as any route.
struct PlanRoute {
  std::vector<Eigen::Vector2d> waypoints_m;
  double cruise_speed_kmh = 9.0;
  double turn_speed_kmh = 4.0;

  template <typename V>
  void VisitFields(V& v) {
    v("waypoints_m", waypoints_m);
    v("cruise_speed_kmh", cruise_speed_kmh);
    v("turn_speed_kmh", turn_speed_kmh);
  }
};

struct PlanFile {
  std::string name = "plan";
  sim::RegionConfig hall;
  sim::WorldPlan world;
  PlanRoute route;

  // The world's lists sit at the top level of the file.
  template <typename V>
  void VisitFields(V& v) {
    v("name", name);
    v("hall", hall);
    world.VisitFields(v);
    v("route", route);
  }
};

// The plan as block YAML; numbers written to read back exactly.
std::string PlanToYaml(const PlanFile& plan);

// Parses a plan strictly (keys left out keep PlanFile's defaults). Throws
// IoError naming source_name, the line and the key path. Does not validate.
PlanFile PlanFromYaml(const std::string& yaml_text, const std::string& source_name);

// The scenario of a plan: its world (WorldConfig::plan, no rows, corridor or
// generated tags) and its route (the waypoints as route.approach_m), the
// vehicle and sensors of sim::DefaultScenario(). Throws IoError
// "source_name: slots[3].corners_m: ..." when the plan is invalid or the
// route leaves the floor or runs through a wall or pillar.
sim::ScenarioConfig ScenarioFromPlan(const PlanFile& plan, const std::string& source_name);

// Reads, validates and converts a plan file (ScenarioFromPlan).
sim::ScenarioConfig LoadPlanFile(const std::filesystem::path& path);

// The plan of any scenario: its built world slot by slot (the floor: hall
// and corridor) and its route's waypoints (laps unrolled).
// ScenarioFromPlan(PlanFromScenario(s)) builds the same slots, walls,
// pillars and tags, and drives the same waypoints.
PlanFile PlanFromScenario(const sim::ScenarioConfig& scenario);

}  // namespace parkslam::io

#endif  // PARKSLAM_IO_WORLD_PLAN_YAML_H_
