#ifndef PARKSLAM_SIM_SCENARIO_CONFIG_H_
#define PARKSLAM_SIM_SCENARIO_CONFIG_H_

// Everything the simulator needs: the parking lot, the route driven through
// it, the vehicle and its sensors. Plain structs with defaults; every field
// carries its unit in its name. Each struct lists its fields once in
// VisitFields(), which the YAML loader (io/scenario_yaml.h) walks, so that a
// field added here is loadable, dumpable and checked for unknown keys
// without further code. The defaults are documented in docs/simulator.md.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "parkslam/common/lot_constants.h"
#include "parkslam/sensor/odometry_spec.h"
#include "parkslam/sensor/vehicle.h"
#include "parkslam/sim/region.h"
#include "parkslam/sim/world_plan.h"

namespace parkslam::sim {

// A straight row of slots. Corner 0 of the first slot sits at origin_m; the
// entrance line runs along direction_deg; the slots extend to the left of
// that direction when far_side_left (else to the right). Separating lines
// meet the entrance line at angle_deg (90 for perpendicular and parallel
// slots). width_m is the distance between neighbouring separating lines
// measured perpendicular to them, depth_m their length.
struct SlotRowConfig {
  std::string kind = "perpendicular";  // perpendicular | angled | parallel
  Eigen::Vector2d origin_m = Eigen::Vector2d::Zero();
  double direction_deg = 0.0;
  bool far_side_left = true;
  int count = 10;
  double width_m = 2.5;
  double depth_m = kStandardSlotDepth_m;
  double angle_deg = 90.0;
  int group_size = 3;        // slots between two gaps; 0: no gaps
  double group_gap_m = 0.8;  // gap between groups, along the row
  bool pillars = true;       // a pillar at the back of every gap
  int first_id = 1;          // painted ID of the first slot
  int id_step = 1;
  int id_digits = 2;  // zero-padded width of painted IDs

  template <typename V>
  void VisitFields(V& v) {
    v("kind", kind);
    v("origin_m", origin_m);
    v("direction_deg", direction_deg);
    v("far_side_left", far_side_left);
    v("count", count);
    v("width_m", width_m);
    v("depth_m", depth_m);
    v("angle_deg", angle_deg);
    v("group_size", group_size);
    v("group_gap_m", group_gap_m);
    v("pillars", pillars);
    v("first_id", first_id);
    v("id_step", id_step);
    v("id_digits", id_digits);
  }
};

// Slots that differ from row to row, as in a real garage: with `enabled`,
// every generated row that is not parallel draws its own slot depth and
// width (uniform in the ranges) and an error of its separating lines' angle
// (uniform in +-angle_error_max_deg), from the world's seed, so that the
// lot stays the same from drive to drive. Off: each row keeps its depth_m,
// width_m and angle_deg. The ranges are those of real garages' plans.
struct SlotVariationConfig {
  bool enabled = false;
  double depth_min_m = 4.8;
  double depth_max_m = 6.2;
  double width_min_m = 2.2;
  double width_max_m = 2.8;
  double angle_error_max_deg = 2.0;

  template <typename V>
  void VisitFields(V& v) {
    v("enabled", enabled);
    v("depth_min_m", depth_min_m);
    v("depth_max_m", depth_max_m);
    v("width_min_m", width_min_m);
    v("width_max_m", width_max_m);
    v("angle_error_max_deg", angle_error_max_deg);
  }
};

// How the lot changed since an earlier drive (docs/simulator.md, "A lot
// that changed"): laid over the built world, with a seed of their own, so
// that two drives of one lot, one with changes and one without, see the
// same lot but for them. Slots are chosen at random among those with a
// painted ID; a moved slot is painted anew moved_slot_shift_m towards its
// aisle (its separating lines stay where its neighbours' are); a repainted
// slot gets a number the lot has nowhere else. A moved tag goes along its
// wall (3-6 m) or to the next face of its pillar; a removed tag is gone.
struct WorldChangesConfig {
  int seed = 1;
  double moved_slot_share = 0.0;
  double moved_slot_shift_m = 0.5;
  double repainted_slot_share = 0.0;
  int moved_tags = 0;
  int removed_tags = 0;

  bool any() const {
    return moved_slot_share > 0.0 || repainted_slot_share > 0.0 || moved_tags > 0 ||
           removed_tags > 0;
  }

  template <typename V>
  void VisitFields(V& v) {
    v("seed", seed);
    v("moved_slot_share", moved_slot_share);
    v("moved_slot_shift_m", moved_slot_shift_m);
    v("repainted_slot_share", repainted_slot_share);
    v("moved_tags", moved_tags);
    v("removed_tags", removed_tags);
  }
};

struct WorldConfig {
  std::string name = "default";
  // Decides which painted IDs are missing or worn: the lot stays the same
  // from drive to drive, whatever the drive's own seed.
  int seed = 1;
  // The hall: a rectangle closed by outer walls.
  RegionConfig hall{0.0, 0.0, 80.0, 50.5};
  // The entrance: a corridor without slots that enters the hall through its
  // west wall; corridor_width_m is also the width of the entrance passage.
  bool corridor = true;
  double corridor_length_m = 40.0;
  double corridor_width_m = 3.0;
  double corridor_center_y_m = 9.1;
  std::vector<SlotRowConfig> rows;
  SlotVariationConfig slot_variation;
  double pillar_size_m = 0.6;
  // AprilTags (tag36h11) on walls and pillar faces inside tag_regions, at most
  // tag_count of them, spread evenly over the candidate places.
  int tag_count = 60;
  double tag_size_m = kDefaultTagSize_m;
  double tag_spacing_m = 3.0;  // between candidate places along a wall
  std::vector<RegionConfig> tag_regions;
  // Share of slots with no painted ID, and with an ID worn beyond reading.
  double id_missing_rate = 0.03;
  double id_worn_rate = 0.05;
  // How the cameras see the lot (scene/lot_scene.h): "grey", the flat grey
  // floor with seven-segment IDs; a named look (LookNames()); or "seed",
  // a look drawn from look_seed. parked_share: the share of slots with a
  // parked car in a named or seeded look (-1: drawn, 0.3-0.7).
  std::string look = "grey";
  int look_seed = 1;
  double parked_share = -1.0;
  // A lot given explicitly (world_plan.h, docs/world_plan.md): when set,
  // the world is the plan's slots, walls, pillars and tags inside `hall`,
  // and the keys above that generate a lot (rows, corridor, pillar size,
  // tags, ID rates) play no part. Left out of the YAML when not set.
  std::optional<WorldPlan> plan;
  // Changes since an earlier drive of the same lot (none by default).
  WorldChangesConfig changes;

  template <typename V>
  void VisitFields(V& v) {
    v("name", name);
    v("seed", seed);
    v("hall", hall);
    v("corridor", corridor);
    v("corridor_length_m", corridor_length_m);
    v("corridor_width_m", corridor_width_m);
    v("corridor_center_y_m", corridor_center_y_m);
    v("rows", rows);
    v("slot_variation", slot_variation);
    v("pillar_size_m", pillar_size_m);
    v("tag_count", tag_count);
    v("tag_size_m", tag_size_m);
    v("tag_spacing_m", tag_spacing_m);
    v("tag_regions", tag_regions);
    v("id_missing_rate", id_missing_rate);
    v("id_worn_rate", id_worn_rate);
    v("look", look);
    v("look_seed", look_seed);
    v("parked_share", parked_share);
    v("plan", plan);
    v("changes", changes);
  }

  bool IsValid(std::string* error) const;
};

// The human drive: through `approach`, then `laps` times round `loop`, then
// through `finish` (all waypoints in the map frame). The driver follows the
// polyline with a small smooth lateral wander and a smooth speed profile.
struct RouteConfig {
  std::vector<Eigen::Vector2d> approach_m;
  std::vector<Eigen::Vector2d> loop_m;
  int laps = 2;
  std::vector<Eigen::Vector2d> finish_m;
  double cruise_speed_kmh = 9.0;
  double turn_speed_kmh = 4.0;
  double max_accel_mps2 = 0.5;
  double max_decel_mps2 = 0.7;
  double lookahead_m = 3.5;
  double lateral_wander_m = 0.15;
  double sample_rate_hz = 100.0;

  template <typename V>
  void VisitFields(V& v) {
    v("approach_m", approach_m);
    v("loop_m", loop_m);
    v("laps", laps);
    v("finish_m", finish_m);
    v("cruise_speed_kmh", cruise_speed_kmh);
    v("turn_speed_kmh", turn_speed_kmh);
    v("max_accel_mps2", max_accel_mps2);
    v("max_decel_mps2", max_decel_mps2);
    v("lookahead_m", lookahead_m);
    v("lateral_wander_m", lateral_wander_m);
    v("sample_rate_hz", sample_rate_hz);
  }
};

// Wheel speed, steering and IMU: the datasheet of sensor/odometry_spec.h,
// from which the simulator draws its noise.
using OdometrySensorConfig = OdometrySensorSpec;

// Slot detection in the fused top view (paper III-A), at observation level.
struct SlotSensorConfig {
  double rate_hz = 10.0;
  // The visible rectangle, centred view_center_x_m ahead of the rear axle
  // (10 m x 10 m as in the ps2.0 top views).
  double view_length_m = 10.0;
  double view_width_m = 10.0;
  double view_center_x_m = 1.4;
  double corner_sigma_m = 0.03;       // at the view centre
  double corner_sigma_per_m = 0.005;  // growth with distance from it
  double miss_rate = 0.05;
  double false_per_frame = 0.02;                   // mean false detections per frame
  double far_corner_observed_rate = 0.2;           // when the far corners are in view
  double standard_depth_m = kStandardSlotDepth_m;  // used to guess unseen far corners
  // An entrance longer than this is taken for a parallel slot, whose unseen
  // far corners are guessed at parallel_depth_m.
  double parallel_min_entrance_m = 4.0;
  double parallel_depth_m = 2.5;
  double far_direction_sigma_deg = 2.0;  // error of the guessed side direction

  template <typename V>
  void VisitFields(V& v) {
    v("rate_hz", rate_hz);
    v("view_length_m", view_length_m);
    v("view_width_m", view_width_m);
    v("view_center_x_m", view_center_x_m);
    v("corner_sigma_m", corner_sigma_m);
    v("corner_sigma_per_m", corner_sigma_per_m);
    v("miss_rate", miss_rate);
    v("false_per_frame", false_per_frame);
    v("far_corner_observed_rate", far_corner_observed_rate);
    v("standard_depth_m", standard_depth_m);
    v("parallel_min_entrance_m", parallel_min_entrance_m);
    v("parallel_depth_m", parallel_depth_m);
    v("far_direction_sigma_deg", far_direction_sigma_deg);
  }
};

// Slot-ID reading errors, per reading of a legible painted ID. The three
// outcomes are exclusive: confusion (one digit read as a confusable one:
// 3/8, 1/7, 5/6, 0/8 ...), partial (one digit unread), unreadable (nothing);
// otherwise every digit is read right.
struct IdSensorConfig {
  double confusion_rate = 0.05;
  double partial_rate = 0.05;
  double unreadable_rate = 0.05;
  // Share of confused digits whose true value is the second hypothesis.
  double true_digit_second_rate = 0.7;

  template <typename V>
  void VisitFields(V& v) {
    v("confusion_rate", confusion_rate);
    v("partial_rate", partial_rate);
    v("unreadable_rate", unreadable_rate);
    v("true_digit_second_rate", true_digit_second_rate);
  }
};

// AprilTags in the front camera (paper III-B), at observation level.
struct TagSensorConfig {
  double rate_hz = 10.0;
  double camera_x_m = 1.8;  // camera position in the vehicle frame
  double camera_y_m = 0.3;
  double camera_yaw_deg = 0.0;
  double horizontal_fov_deg = 90.0;
  double min_range_m = 0.5;
  double max_range_m = 20.0;        // the paper discards tags at 20 m or more
  double max_incidence_deg = 70.0;  // between tag normal and line of sight
  double miss_rate = 0.03;          // at close range
  double miss_rate_at_max_range = 0.5;
  double range_sigma_m = 0.01;
  double range_sigma_per_m = 0.01;
  double bearing_sigma_rad = 0.002;
  double bearing_sigma_per_m = 0.0002;
  double yaw_sigma_rad = 0.03;
  double yaw_sigma_per_m = 0.01;

  template <typename V>
  void VisitFields(V& v) {
    v("rate_hz", rate_hz);
    v("camera_x_m", camera_x_m);
    v("camera_y_m", camera_y_m);
    v("camera_yaw_deg", camera_yaw_deg);
    v("horizontal_fov_deg", horizontal_fov_deg);
    v("min_range_m", min_range_m);
    v("max_range_m", max_range_m);
    v("max_incidence_deg", max_incidence_deg);
    v("miss_rate", miss_rate);
    v("miss_rate_at_max_range", miss_rate_at_max_range);
    v("range_sigma_m", range_sigma_m);
    v("range_sigma_per_m", range_sigma_per_m);
    v("bearing_sigma_rad", bearing_sigma_rad);
    v("bearing_sigma_per_m", bearing_sigma_per_m);
    v("yaw_sigma_rad", yaw_sigma_rad);
    v("yaw_sigma_per_m", yaw_sigma_per_m);
  }
};

// The IMU's compass as it behaves indoors. A magnetometer near steel
// (pillars, parked cars) reads a field bent by several degrees; the bend
// varies with the car's place, not with time. model:
//   disturbed  the AHRS heading of odometry (bias, noise) plus a disturbance
//              field: each pillar and each parked car adds a_k
//              exp(-r^2 / (2 steel_range_m^2)), a_k ~ N(0, steel_sigma_deg);
//              a smooth background (rebar, cables) of three plane waves of
//              background_wavelength_m adds background_sigma_deg in all.
//   clean      the AHRS heading with its bias and noise only.
//   none       no compass: a gyro-only IMU (imu.csv's heading_rad empty).
struct CompassConfig {
  std::string model = "disturbed";  // disturbed | clean | none
  double steel_sigma_deg = 8.0;
  double steel_range_m = 3.0;
  double parked_car_share = 0.5;  // slots holding a (steel) car
  double background_sigma_deg = 2.0;
  double background_wavelength_m = 25.0;

  template <typename V>
  void VisitFields(V& v) {
    v("model", model);
    v("steel_sigma_deg", steel_sigma_deg);
    v("steel_range_m", steel_range_m);
    v("parked_car_share", parked_car_share);
    v("background_sigma_deg", background_sigma_deg);
    v("background_wavelength_m", background_wavelength_m);
  }
};

struct SensorConfig {
  OdometrySensorConfig odometry;
  CompassConfig compass;
  SlotSensorConfig slots;
  IdSensorConfig ids;
  TagSensorConfig tags;

  template <typename V>
  void VisitFields(V& v) {
    v("odometry", odometry);
    v("compass", compass);
    v("slots", slots);
    v("ids", ids);
    v("tags", tags);
  }
};

}  // namespace parkslam::sim

namespace parkslam::sim {

struct ScenarioConfig {
  WorldConfig world;
  RouteConfig route;
  VehicleParameters vehicle;
  SensorConfig sensors;

  template <typename V>
  void VisitFields(V& v) {
    v("world", world);
    v("route", route);
    v("vehicle", vehicle);
    v("sensors", sensors);
  }

  // Checks ranges and consistency; on failure names the field in *error.
  bool IsValid(std::string* error) const;
};

// The built-in world `default`, modelled on the paper's test lot: a hall of
// about 4000 m2 with 100+ slots in perpendicular, angled and parallel rows,
// pillars, a 3 m entrance and a 40 m corridor, 60 tags near the entrance and
// in the corridor, and an eastern part without any tag.
ScenarioConfig DefaultScenario();

// The values of WorldConfig::look: "grey", "seed", then the named looks
// (bright indoor epoxy, dim worn concrete, an underground deck with lamp
// glare and puddles, outdoor asphalt with sun and hard shadows, yellow
// paint, faded paint with repaints).
const std::vector<std::string>& LookNames();

}  // namespace parkslam::sim

#endif  // PARKSLAM_SIM_SCENARIO_CONFIG_H_
