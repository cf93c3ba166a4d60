#include "parkslam/sim/scenario_config.h"

#include <algorithm>

#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

#include "parkslam/common/angles.h"
#include "parkslam/common/field_checker.h"
#include "parkslam/common/plausible_ranges.h"
#include "parkslam/map/semantic_map.h"
#include "parkslam/sim/route.h"
#include "parkslam/sim/world.h"
#include "parkslam/sim/world_plan.h"

namespace parkslam::sim {
namespace {

void CheckRegion(const RegionConfig& r, const std::string& field, FieldChecker& c) {
  c.Point({r.min_x_m, r.min_y_m}, field);
  c.Point({r.max_x_m, r.max_y_m}, field);
}

void CheckWorld(const WorldConfig& w, FieldChecker& c) {
  c.Require(!w.name.empty(), "world.name", "must not be empty");
  {
    const std::vector<std::string>& looks = LookNames();
    std::string known;
    for (const std::string& l : looks) known += (known.empty() ? "" : ", ") + l;
    c.Require(std::find(looks.begin(), looks.end(), w.look) != looks.end(), "world.look",
              "must be one of " + known);
  }
  c.Require(w.look_seed >= 0, "world.look_seed", "must be non-negative");
  // -1 is the sentinel "drawn"; any other negative number is a typo.
  c.Require(w.parked_share == -1.0 || (w.parked_share >= 0.0 && w.parked_share <= 1.0),
            "world.parked_share", "must be in [0, 1], or -1: drawn from 0.3-0.7");
  c.Require(w.seed >= 0, "world.seed", "must be non-negative");
  c.Require(w.changes.seed >= 0, "world.changes.seed", "must be non-negative");
  c.Rate(w.changes.moved_slot_share, "world.changes.moved_slot_share");
  c.Rate(w.changes.repainted_slot_share, "world.changes.repainted_slot_share");
  c.Require(w.changes.moved_slot_share + w.changes.repainted_slot_share <= 1.0,
            "world.changes.repainted_slot_share",
            "with moved_slot_share, must be at most 1 (a slot changes once)");
  c.InRange(w.changes.moved_slot_shift_m, 0.1, 3.0, "world.changes.moved_slot_shift_m", "m");
  c.Require(w.changes.moved_tags >= 0 && w.changes.moved_tags <= 1000, "world.changes.moved_tags",
            "must be in [0, 1000]");
  c.Require(w.changes.removed_tags >= 0 && w.changes.removed_tags <= 1000,
            "world.changes.removed_tags", "must be in [0, 1000]");
  CheckRegion(w.hall, "world.hall", c);
  c.InRange(w.hall.max_x_m - w.hall.min_x_m, kMinHallSide_m, kMaxHallSide_m, "world.hall",
            "m (max_x_m - min_x_m)");
  c.InRange(w.hall.max_y_m - w.hall.min_y_m, kMinHallSide_m, kMaxHallSide_m, "world.hall",
            "m (max_y_m - min_y_m)");
  if (w.corridor) {
    c.PositiveAtMost(w.corridor_length_m, kMaxHallSide_m, "world.corridor_length_m", "m");
    c.InRange(w.corridor_width_m, kMinCorridorWidth_m, kMaxCorridorWidth_m,
              "world.corridor_width_m", "m");
    c.Require(w.corridor_center_y_m - w.corridor_width_m / 2 > w.hall.min_y_m &&
                  w.corridor_center_y_m + w.corridor_width_m / 2 < w.hall.max_y_m,
              "world.corridor_center_y_m", "corridor must meet the west wall");
  }
  for (size_t i = 0; i < w.rows.size(); ++i) {
    const SlotRowConfig& r = w.rows[i];
    const std::string p = "world.rows[" + std::to_string(i) + "].";
    c.Require(SlotKindFromString(r.kind).has_value(), p + "kind",
              "must be perpendicular, angled or parallel");
    c.Require(r.count >= 1 && r.count <= 1000, p + "count", "must be in [1, 1000]");
    c.InRange(r.width_m, kMinSlotSide_m, kMaxSlotSide_m, p + "width_m", "m");
    c.InRange(r.depth_m, kMinSlotSide_m, kMaxSlotSide_m, p + "depth_m", "m");
    c.InRange(r.angle_deg, kMinSlotAngle_deg, kMaxSlotAngle_deg, p + "angle_deg", "deg");
    c.Magnitude(r.direction_deg, kMaxAngle_deg, p + "direction_deg", "deg");
    c.Require(r.group_size >= 0, p + "group_size", "must be non-negative");
    c.InRange(r.group_gap_m, 0.0, kMaxHallSide_m, p + "group_gap_m", "m");
    c.Require(r.first_id >= 0 && r.id_step >= 0, p + "first_id", "IDs must be non-negative");
    c.Require(r.id_digits >= 1 && r.id_digits <= 4, p + "id_digits", "must be in [1, 4]");
    c.Point(r.origin_m, p + "origin_m");
  }
  const SlotVariationConfig& v = w.slot_variation;
  c.InRange(v.depth_min_m, kMinSlotSide_m, kMaxSlotSide_m, "world.slot_variation.depth_min_m", "m");
  c.InRange(v.depth_max_m, v.depth_min_m, kMaxSlotSide_m, "world.slot_variation.depth_max_m",
            "m (at least depth_min_m)");
  c.InRange(v.width_min_m, kMinSlotSide_m, kMaxSlotSide_m, "world.slot_variation.width_min_m", "m");
  c.InRange(v.width_max_m, v.width_min_m, kMaxSlotSide_m, "world.slot_variation.width_max_m",
            "m (at least width_min_m)");
  c.InRange(v.angle_error_max_deg, 0.0, 10.0, "world.slot_variation.angle_error_max_deg", "deg");
  // Painted IDs must be unique across rows: the map keys slots by them.
  std::set<std::string> painted;
  for (size_t i = 0; i < w.rows.size() && c.ok(); ++i) {
    const SlotRowConfig& r = w.rows[i];
    for (int k = 0; k < r.count; ++k) {
      std::string id = std::to_string(r.first_id + k * r.id_step);
      if (static_cast<int>(id.size()) < r.id_digits) {
        id.insert(0, static_cast<size_t>(r.id_digits) - id.size(), '0');
      }
      c.Require(painted.insert(id).second, "world.rows[" + std::to_string(i) + "].first_id",
                "gives a painted ID that another slot already has");
      if (!c.ok()) break;
    }
  }
  c.PositiveAtMost(w.pillar_size_m, kMaxHallSide_m, "world.pillar_size_m", "m");
  c.Require(w.tag_count >= 0 && w.tag_count <= 587, "world.tag_count",
            "must be in [0, 587] (the tag36h11 family)");
  c.PositiveAtMost(w.tag_size_m, kMaxTagSize_m, "world.tag_size_m", "m");
  c.InRange(w.tag_spacing_m, 0.5, kMaxHallSide_m, "world.tag_spacing_m", "m");
  for (size_t i = 0; i < w.tag_regions.size(); ++i) {
    CheckRegion(w.tag_regions[i], "world.tag_regions[" + std::to_string(i) + "]", c);
  }
  c.Rate(w.id_missing_rate, "world.id_missing_rate");
  c.Rate(w.id_worn_rate, "world.id_worn_rate");
  if (w.plan && c.ok()) {
    std::string plan_error;
    c.Require(IsValidPlan(*w.plan, w.hall, "world.plan", &plan_error), plan_error);
  }
}

// The route of a plan's world stays on its floor and clear of its walls and
// pillars (a generated lot leaves its aisles to the route's author).
void CheckRouteInPlan(const ScenarioConfig& s, FieldChecker& c) {
  if (!s.world.plan || !c.ok()) return;
  const bool approach_only = s.route.loop_m.empty() && s.route.finish_m.empty();
  std::string error;
  c.Require(
      IsDrivableRoute(RouteWaypoints(s.route), FloorRegions(s.world), BuildWorld(s.world),
                      approach_only ? "route.approach_m" : "route (waypoints in order)", &error),
      error);
}

void CheckWaypoints(const std::vector<Eigen::Vector2d>& points, const std::string& field,
                    FieldChecker& c) {
  for (size_t i = 0; i < points.size(); ++i) {
    c.Point(points[i], field + "[" + std::to_string(i) + "]");
  }
}

// The length of a polyline through `points` (closed: back to the first).
double PolylineLength(const std::vector<Eigen::Vector2d>& points, bool closed) {
  double length_m = 0.0;
  for (size_t i = 1; i < points.size(); ++i) length_m += (points[i] - points[i - 1]).norm();
  if (closed && points.size() > 1) length_m += (points.front() - points.back()).norm();
  return length_m;
}

// Bounds on the drive a route makes: a world file of 100,000 waypoints (a
// 20 km drive back and forth) took 5 GB before its simulation ended.
// A long drive costs about 16 MB a km (80 laps of the default lot, 20 km:
// 420 MB); 40 km is 4.4 h at 9 km/h.
constexpr size_t kMaxRouteWaypoints = 10'000;
constexpr double kMaxRouteLength_m = 40'000.0;

void CheckRoute(const RouteConfig& r, FieldChecker& c) {
  c.Require(r.approach_m.size() + r.loop_m.size() + r.finish_m.size() >= 2, "route",
            "needs at least two waypoints");
  CheckWaypoints(r.approach_m, "route.approach_m", c);
  CheckWaypoints(r.loop_m, "route.loop_m", c);
  CheckWaypoints(r.finish_m, "route.finish_m", c);
  const size_t waypoints = r.approach_m.size() + r.loop_m.size() + r.finish_m.size();
  std::string too_many = std::to_string(waypoints);
  too_many.append(" waypoints; a route has at most ")
      .append(std::to_string(kMaxRouteWaypoints))
      .append(" (docs/plausible_ranges.md)");
  c.Require(waypoints <= kMaxRouteWaypoints, "route", too_many);
  const double length_m = PolylineLength(r.approach_m, false) + PolylineLength(r.finish_m, false) +
                          std::max(0, r.laps) * PolylineLength(r.loop_m, true);
  std::string too_long = "drives ";
  too_long.append(Limit(length_m))
      .append(" m (approach, laps x loop, finish); a route drives at most ")
      .append(Limit(kMaxRouteLength_m))
      .append(" m (docs/plausible_ranges.md)");
  c.Require(length_m <= kMaxRouteLength_m, "route", too_long);
  c.Require(r.laps >= 0 && r.laps <= 1000, "route.laps", "must be in [0, 1000]");
  c.Require(r.laps == 0 || r.loop_m.size() >= 2, "route.loop_m",
            "needs at least two waypoints when laps > 0");
  c.Require(r.cruise_speed_kmh > kMinDriveSpeed_kmh && r.cruise_speed_kmh <= kMaxDriveSpeed_kmh,
            "route.cruise_speed_kmh",
            "must be in (" + Limit(kMinDriveSpeed_kmh) + ", " + Limit(kMaxDriveSpeed_kmh) + "]");
  c.Require(r.turn_speed_kmh > kMinDriveSpeed_kmh && r.turn_speed_kmh <= r.cruise_speed_kmh,
            "route.turn_speed_kmh",
            "must be in (" + Limit(kMinDriveSpeed_kmh) + ", cruise_speed_kmh]");
  c.PositiveAtMost(r.max_accel_mps2, kMaxAcceleration_mps2, "route.max_accel_mps2", "m/s^2");
  c.PositiveAtMost(r.max_decel_mps2, kMaxAcceleration_mps2, "route.max_decel_mps2", "m/s^2");
  c.InRange(r.lookahead_m, 1.0, kMaxHallSide_m, "route.lookahead_m", "m");
  c.InRange(r.lateral_wander_m, 0.0, kMaxHallSide_m, "route.lateral_wander_m", "m");
  c.InRange(r.sample_rate_hz, kMinRouteSampleRate_hz, kMaxSensorRate_hz, "route.sample_rate_hz",
            "Hz");
}

void CheckSlotSensor(const SlotSensorConfig& sl, FieldChecker& c) {
  c.InRange(sl.rate_hz, kMinSensorRate_hz, kMaxCameraRate_hz, "sensors.slots.rate_hz", "Hz");
  c.InRange(sl.view_length_m, kMinTopViewSide_m, kMaxTopViewSide_m, "sensors.slots.view_length_m",
            "m");
  c.InRange(sl.view_width_m, kMinTopViewSide_m, kMaxTopViewSide_m, "sensors.slots.view_width_m",
            "m");
  c.Magnitude(sl.view_center_x_m, kMaxTopViewSide_m / 2, "sensors.slots.view_center_x_m", "m");
  c.NonNegative(sl.corner_sigma_m, "sensors.slots.corner_sigma_m");
  c.InRange(sl.corner_sigma_per_m, 0.0, kMaxRelativeSigma, "sensors.slots.corner_sigma_per_m", "");
  // The sigma of a corner anywhere in the view, as observations carry it.
  c.Require(
      sl.corner_sigma_m + sl.corner_sigma_per_m * std::hypot(sl.view_length_m, sl.view_width_m) <=
          kMaxPositionSigma_m,
      "sensors.slots.corner_sigma_m",
      "grows beyond " + Limit(kMaxPositionSigma_m) +
          " m across the view (corner_sigma_m + corner_sigma_per_m * view diagonal)");
  c.Rate(sl.miss_rate, "sensors.slots.miss_rate");
  c.Require(sl.false_per_frame >= 0 && sl.false_per_frame <= 5, "sensors.slots.false_per_frame",
            "must be in [0, 5]");
  c.Rate(sl.far_corner_observed_rate, "sensors.slots.far_corner_observed_rate");
  c.InRange(sl.standard_depth_m, kMinSlotSide_m, kMaxSlotSide_m, "sensors.slots.standard_depth_m",
            "m");
  c.InRange(sl.parallel_min_entrance_m, kMinSlotSide_m, kMaxSlotSide_m,
            "sensors.slots.parallel_min_entrance_m", "m");
  c.InRange(sl.parallel_depth_m, kMinSlotSide_m, kMaxSlotSide_m, "sensors.slots.parallel_depth_m",
            "m");
  c.InRange(sl.far_direction_sigma_deg, 0.0, RadToDeg(kMaxAngleSigma_rad),
            "sensors.slots.far_direction_sigma_deg", "deg");
}

void CheckIdSensor(const IdSensorConfig& id, FieldChecker& c) {
  c.Rate(id.confusion_rate, "sensors.ids.confusion_rate");
  c.Rate(id.partial_rate, "sensors.ids.partial_rate");
  c.Rate(id.unreadable_rate, "sensors.ids.unreadable_rate");
  c.Require(id.confusion_rate + id.partial_rate + id.unreadable_rate <= 1.0, "sensors.ids",
            "confusion_rate + partial_rate + unreadable_rate must not exceed 1");
  c.Rate(id.true_digit_second_rate, "sensors.ids.true_digit_second_rate");
}

void CheckTagSensor(const TagSensorConfig& t, FieldChecker& c) {
  c.InRange(t.rate_hz, kMinSensorRate_hz, kMaxCameraRate_hz, "sensors.tags.rate_hz", "Hz");
  c.Magnitude(t.camera_x_m, kMaxCameraOffset_m, "sensors.tags.camera_x_m", "m");
  c.Magnitude(t.camera_y_m, kMaxCameraOffset_m, "sensors.tags.camera_y_m", "m");
  c.Magnitude(t.camera_yaw_deg, kMaxAngle_deg, "sensors.tags.camera_yaw_deg", "deg");
  c.Require(t.horizontal_fov_deg > 1 && t.horizontal_fov_deg < 180,
            "sensors.tags.horizontal_fov_deg", "must be in (1, 180)");
  c.Require(t.min_range_m >= 0 && t.max_range_m > t.min_range_m, "sensors.tags.max_range_m",
            "must exceed min_range_m");
  // Tags are reported in the vehicle frame: camera position plus range.
  c.Require(std::hypot(t.camera_x_m, t.camera_y_m) + t.max_range_m <= kMaxObservationRange_m,
            "sensors.tags.max_range_m",
            "reaches beyond " + Limit(kMaxObservationRange_m) +
                " m from the vehicle (camera position + max_range_m)");
  c.Require(t.max_incidence_deg > 0 && t.max_incidence_deg < 90, "sensors.tags.max_incidence_deg",
            "must be in (0, 90)");
  c.Rate(t.miss_rate, "sensors.tags.miss_rate");
  c.Rate(t.miss_rate_at_max_range, "sensors.tags.miss_rate_at_max_range");
  c.NonNegative(t.range_sigma_m, "sensors.tags.range_sigma_m");
  c.NonNegative(t.range_sigma_per_m, "sensors.tags.range_sigma_per_m");
  c.NonNegative(t.bearing_sigma_rad, "sensors.tags.bearing_sigma_rad");
  c.NonNegative(t.bearing_sigma_per_m, "sensors.tags.bearing_sigma_per_m");
  c.NonNegative(t.yaw_sigma_rad, "sensors.tags.yaw_sigma_rad");
  c.NonNegative(t.yaw_sigma_per_m, "sensors.tags.yaw_sigma_per_m");
  // The noise at the farthest range, as observations carry it: along and
  // across the line of sight, and of the tag's yaw.
  const double range_sigma_m = t.range_sigma_m + t.range_sigma_per_m * t.max_range_m;
  const double across_sigma_m =
      t.max_range_m * (t.bearing_sigma_rad + t.bearing_sigma_per_m * t.max_range_m);
  const double yaw_sigma_rad = t.yaw_sigma_rad + t.yaw_sigma_per_m * t.max_range_m;
  c.Require(range_sigma_m <= kMaxPositionSigma_m, "sensors.tags.range_sigma_m",
            "grows beyond " + Limit(kMaxPositionSigma_m) +
                " m at max_range_m (range_sigma_m + range_sigma_per_m * max_range_m)");
  c.Require(across_sigma_m <= kMaxPositionSigma_m, "sensors.tags.bearing_sigma_rad",
            "gives more than " + Limit(kMaxPositionSigma_m) +
                " m across the line of sight at max_range_m");
  c.Require(yaw_sigma_rad <= kMaxAngleSigma_rad, "sensors.tags.yaw_sigma_rad",
            "grows beyond " + Limit(kMaxAngleSigma_rad) +
                " rad at max_range_m (yaw_sigma_rad + yaw_sigma_per_m * max_range_m)");
}

void CheckCompass(const CompassConfig& s, FieldChecker& c) {
  c.Require(s.model == "disturbed" || s.model == "clean" || s.model == "none",
            "sensors.compass.model", "must be disturbed, clean or none, got '" + s.model + "'");
  c.InRange(s.steel_sigma_deg, 0.0, 90.0, "sensors.compass.steel_sigma_deg", "deg");
  c.Between(s.steel_range_m, 0.1, 50.0, "sensors.compass.steel_range_m", "m");
  c.Rate(s.parked_car_share, "sensors.compass.parked_car_share");
  c.InRange(s.background_sigma_deg, 0.0, 90.0, "sensors.compass.background_sigma_deg", "deg");
  c.Between(s.background_wavelength_m, 1.0, 10000.0, "sensors.compass.background_wavelength_m",
            "m");
}

void CheckSensors(const SensorConfig& s, FieldChecker& c) {
  std::string odometry_error;
  c.Require(s.odometry.IsValid(&odometry_error), odometry_error);
  CheckCompass(s.compass, c);
  CheckSlotSensor(s.slots, c);
  CheckIdSensor(s.ids, c);
  CheckTagSensor(s.tags, c);
}

SlotRowConfig Row(const char* kind, double x, double y, bool far_side_left, int count, int first_id,
                  int id_digits) {
  SlotRowConfig row;
  row.kind = kind;
  row.origin_m = Eigen::Vector2d(x, y);
  row.far_side_left = far_side_left;
  row.count = count;
  row.first_id = first_id;
  row.id_digits = id_digits;
  return row;
}

}  // namespace

const std::vector<std::string>& LookNames() {
  static const std::vector<std::string> kNames = {"grey",        "seed",    "epoxy",  "concrete",
                                                  "underground", "outdoor", "yellow", "faded"};
  return kNames;
}

bool WorldConfig::IsValid(std::string* error) const {
  FieldChecker checker(error);
  CheckWorld(*this, checker);
  return checker.ok();
}

bool ScenarioConfig::IsValid(std::string* error) const {
  FieldChecker checker(error);
  CheckWorld(world, checker);
  CheckRoute(route, checker);
  CheckRouteInPlan(*this, checker);
  // The vehicle's own message, taken only after IsValid wrote it.
  std::string vehicle_error;
  const bool vehicle_ok = vehicle.IsValid(&vehicle_error);
  if (vehicle_error.rfind("vehicle.", 0) == 0) vehicle_error.erase(0, 8);
  checker.Require(vehicle_ok, "vehicle", vehicle_error.c_str());
  CheckSensors(sensors, checker);
  return checker.ok();
}

ScenarioConfig DefaultScenario() {
  ScenarioConfig config;
  WorldConfig& w = config.world;
  w.name = "default";
  w.hall = {0.0, 0.0, 87.5, 50.5};
  // The corridor continues aisle 1 (y = 5.6 .. 12.6) westwards.
  w.corridor_center_y_m = 9.1;

  // South to north: row A against the south wall facing aisle 1; rows B and C
  // back to back between aisles 1 and 2 with pillars on their shared back
  // line; row D of 60-degree angled slots facing aisle 2; row E facing aisle
  // 3 with three-digit IDs; a parallel row F along the north wall; row G
  // along the east wall, facing the east cross aisle.
  w.rows.push_back(Row("perpendicular", 8.0, 5.6, false, 24, 1, 2));
  w.rows.back().pillars = false;  // against the wall
  w.rows.push_back(Row("perpendicular", 8.0, 12.6, true, 24, 25, 2));
  w.rows.push_back(Row("perpendicular", 8.0, 23.2, false, 24, 49, 2));
  w.rows.back().pillars = false;  // shares the pillars of row B
  SlotRowConfig angled = Row("angled", 8.0, 30.2, true, 21, 73, 2);
  angled.angle_deg = 60.0;
  w.rows.push_back(angled);
  w.rows.push_back(Row("perpendicular", 8.0, 40.7, false, 24, 101, 3));
  w.rows.back().pillars = false;  // row D's pillars stand just behind
  SlotRowConfig parallel = Row("parallel", 8.0, 47.7, true, 10, 201, 3);
  parallel.width_m = 6.0;
  parallel.depth_m = 2.5;
  parallel.group_size = 0;
  parallel.pillars = false;
  w.rows.push_back(parallel);
  SlotRowConfig east = Row("perpendicular", 82.2, 11.6, false, 14, 301, 3);
  east.direction_deg = 90.0;
  east.pillars = false;  // against the wall
  w.rows.push_back(east);

  // Tags near the entrance and in the corridor (the paper: 60 tags); the
  // eastern part of the hall (x > 30 m) has none.
  w.tag_count = 60;
  w.tag_regions.push_back({-41.0, 6.0, 0.5, 12.2});
  w.tag_regions.push_back({-0.5, -0.5, 30.0, 51.0});

  RouteConfig& r = config.route;
  const double aisle1_y = 9.1, aisle2_y = 26.7, aisle3_y = 44.2;
  // Cross aisles: west x = 0 .. 8, east x = 76.1 .. 82.2 (from the angled
  // row's back corners to row G's entrance).
  const double west_x = 4.0, east_x = 79.0;
  r.approach_m = {{-37.0, aisle1_y}, {-10.0, aisle1_y}};
  r.loop_m = {{west_x, aisle1_y}, {east_x, aisle1_y}, {east_x, aisle2_y}, {west_x, aisle2_y}};
  r.laps = 2;
  // After the laps: along aisle 1 once more, up the east cross aisle and
  // back west through aisle 3, ending in the west cross aisle.
  r.finish_m = {{east_x, aisle1_y}, {east_x, aisle3_y}, {west_x, aisle3_y}, {west_x, 34.0}};
  return config;
}

}  // namespace parkslam::sim
