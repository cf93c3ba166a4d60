#include "parkslam/io/map_json.h"

#include <cmath>
#include <map>
#include <vector>

#include "parkslam/common/plausible_ranges.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/json_util.h"
#include "parkslam/io/text_util.h"

namespace parkslam::io {
namespace {

using json_util::Json;
using json_util::JsonPath;
using json_util::JsonReader;

constexpr double kLengthScale = 1e3;  // millimetres
constexpr double kFineScale = 1e6;    // angles and standard deviations

double Rounded(double value, double scale) {
  const double rounded = std::round(value * scale) / scale;
  return rounded == 0.0 ? 0.0 : rounded;  // no "-0.0"
}

Json PointJson(const Eigen::Vector2d& p) {
  return Json::array({Rounded(p.x(), kLengthScale), Rounded(p.y(), kLengthScale)});
}

Json SlotJson(const MapSlot& slot) {
  Json corners = Json::array(), observed = Json::array(), sigmas = Json::array();
  for (int c = 0; c < kSlotCorners; ++c) {
    corners.push_back(PointJson(slot.corners_map[c]));
    observed.push_back(slot.corner_observed[c]);
    sigmas.push_back(Rounded(slot.corner_sigma_m[c], kFineScale));
  }
  Json j{{"id", slot.id},
         {"temporary", slot.temporary},
         {"id_legible", slot.id_legible},
         {"kind", ToString(slot.kind)},
         {"corners", corners},
         {"corner_observed", observed},
         {"corner_sigma_m", sigmas},
         {"observations", slot.observation_count}};
  if (!slot.last_confirmed.empty()) j["last_confirmed"] = slot.last_confirmed;
  return j;
}

Json TagJson(const MapTag& tag) {
  Json j{{"id", tag.tag_id},
         {"x", Rounded(tag.p_map.x(), kLengthScale)},
         {"y", Rounded(tag.p_map.y(), kLengthScale)},
         {"yaw", Rounded(tag.yaw_map_rad, kFineScale)},
         {"size_m", Rounded(tag.size_m, kLengthScale)},
         {"obstacle", tag.obstacle_index}};
  if (!tag.last_confirmed.empty()) j["last_confirmed"] = tag.last_confirmed;
  return j;
}

Json ObstacleJson(const MapObstacle& obstacle) {
  Json points = Json::array();
  for (const Eigen::Vector2d& p : obstacle.points_map) points.push_back(PointJson(p));
  return Json{{"kind", ToString(obstacle.kind)}, {"points", points}};
}

// Keys in the order a reader expects them; the rest follow sorted.
const std::vector<std::string>& KeyOrder() {
  static const std::vector<std::string> order = {
      "format",       "version",    "frame", "units",   "length",          "angle",
      "metadata",     "entrance",   "slots", "tags",    "obstacles",       "id",
      "temporary",    "id_legible", "kind",  "corners", "corner_observed", "corner_sigma_m",
      "observations", "x",          "y",     "yaw",     "size_m",          "obstacle",
      "points"};
  return order;
}

void CheckHeader(const Json& json, const JsonReader& r, const JsonPath& root) {
  if (!json.is_object()) r.Fail(root, "expected a JSON object (a parkslam map)");
  const JsonPath format = root.Key("format");
  if (!json.contains("format")) r.Fail(format, "missing key (not a parkslam map)");
  const std::string& name = r.String(json["format"], format);
  if (name != kMapFormatName) {
    r.Fail(format, "expected '" + std::string(kMapFormatName) + "', got '" + name + "'");
  }
  const JsonPath version = root.Key("version");
  if (!json.contains("version")) r.Fail(version, "missing key");
  const std::int64_t number = r.Integer(json["version"], version);
  if (number != kMapFormatVersion) {
    r.Fail(version, "unsupported version " + std::to_string(number) + " (this build reads " +
                        std::to_string(kMapFormatVersion) + ")");
  }
  r.ExpectObject(json, root,
                 {"format", "version", "frame", "units", "metadata", "slots", "tags", "obstacles"},
                 {"entrance"});
  const JsonPath frame = root.Key("frame");
  if (r.String(json["frame"], frame) != "map") r.Fail(frame, "expected 'map'");
  const JsonPath units = root.Key("units");
  r.ExpectObject(json["units"], units, {"length", "angle"});
  const JsonPath length = units.Key("length");
  const JsonPath angle = units.Key("angle");
  if (r.String(json["units"]["length"], length) != "m") r.Fail(length, "expected 'm'");
  if (r.String(json["units"]["angle"], angle) != "rad") r.Fail(angle, "expected 'rad'");
}

std::map<std::string, std::string> ReadMetadata(const Json& j, const JsonReader& r,
                                                const JsonPath& path) {
  if (!j.is_object()) r.Fail(path, "expected an object of strings");
  std::map<std::string, std::string> metadata;
  for (const auto& item : j.items()) {
    const JsonPath value_path = path.Key(item.key().c_str());
    metadata[item.key()] = r.String(item.value(), value_path);
  }
  return metadata;
}

MapSlot ReadSlot(const Json& j, const JsonReader& r, const JsonPath& path) {
  r.ExpectObject(j, path,
                 {"id", "temporary", "id_legible", "kind", "corners", "corner_observed",
                  "corner_sigma_m", "observations"},
                 {"last_confirmed"});
  MapSlot slot;
  slot.id = r.String(j["id"], path.Key("id"));
  // An ID as painted ("38", "B105") or temporary ("t12"): short, printable.
  constexpr std::size_t kMaxIdLength = 16;
  if (slot.id.size() > kMaxIdLength) {
    r.Fail(path.Key("id"), std::to_string(slot.id.size()) + " characters; an ID has at most " +
                               std::to_string(kMaxIdLength));
  }
  for (const char c : slot.id) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      r.Fail(path.Key("id"), "holds a control character");
    }
  }
  slot.temporary = r.Bool(j["temporary"], path.Key("temporary"));
  slot.id_legible = r.Bool(j["id_legible"], path.Key("id_legible"));
  const JsonPath kind_path = path.Key("kind");
  const std::string& kind = r.String(j["kind"], kind_path);
  const std::optional<SlotKind> slot_kind = SlotKindFromString(kind);
  if (!slot_kind) {
    r.Fail(kind_path, "expected perpendicular, angled or parallel, got '" + kind + "'");
  }
  slot.kind = *slot_kind;
  const JsonPath corners = path.Key("corners");
  const JsonPath observed = path.Key("corner_observed");
  const JsonPath sigmas = path.Key("corner_sigma_m");
  r.ExpectArray(j["corners"], corners, kSlotCorners, "points");
  r.ExpectArray(j["corner_observed"], observed, kSlotCorners, "booleans");
  r.ExpectArray(j["corner_sigma_m"], sigmas, kSlotCorners, "numbers");
  for (int c = 0; c < kSlotCorners; ++c) {
    const auto i = static_cast<std::size_t>(c);
    const JsonPath corner = corners.Index(i);
    const JsonPath flag = observed.Index(i);
    const JsonPath sigma = sigmas.Index(i);
    slot.corners_map[i] = r.Point(j["corners"][i], corner, kMaxCoordinate_m, "m");
    slot.corner_observed[i] = r.Bool(j["corner_observed"][i], flag);
    slot.corner_sigma_m[i] =
        r.NumberIn(j["corner_sigma_m"][i], sigma, 0.0, kMaxPositionSigma_m, "m");
  }
  json_util::CheckSlotArea(slot.corners_map, r, corners);
  const JsonPath count = path.Key("observations");
  slot.observation_count = r.Int(j["observations"], count);
  if (slot.observation_count < 0) r.Fail(count, "must not be negative");
  if (j.contains("last_confirmed")) {
    slot.last_confirmed = r.String(j["last_confirmed"], path.Key("last_confirmed"));
  }
  return slot;
}

MapTag ReadTag(const Json& j, const JsonReader& r, const JsonPath& path,
               std::size_t obstacle_count) {
  r.ExpectObject(j, path, {"id", "x", "y", "yaw", "size_m", "obstacle"}, {"last_confirmed"});
  MapTag tag;
  const JsonPath id = path.Key("id");
  tag.tag_id = r.Int(j["id"], id);
  if (tag.tag_id < 0 || tag.tag_id >= kTagIdCount) {
    r.Fail(id, "must be a tag36h11 ID in [0, " + std::to_string(kTagIdCount - 1) + "], got " +
                   std::to_string(tag.tag_id));
  }
  tag.p_map = Eigen::Vector2d(r.BoundedNumber(j["x"], path.Key("x"), kMaxCoordinate_m, "m"),
                              r.BoundedNumber(j["y"], path.Key("y"), kMaxCoordinate_m, "m"));
  tag.yaw_map_rad = r.BoundedNumber(j["yaw"], path.Key("yaw"), kMaxAngle_rad, "rad");
  const JsonPath size = path.Key("size_m");
  tag.size_m = r.Number(j["size_m"], size);
  if (tag.size_m <= 0.0) r.Fail(size, "must be positive");
  if (tag.size_m > kMaxTagSize_m) {
    r.Fail(size, text::BeyondPlausible(tag.size_m, kMaxTagSize_m, "m"));
  }
  const JsonPath obstacle = path.Key("obstacle");
  tag.obstacle_index = r.Int(j["obstacle"], obstacle);
  if (tag.obstacle_index < -1 || tag.obstacle_index >= static_cast<std::int64_t>(obstacle_count)) {
    r.Fail(obstacle, "index " + std::to_string(tag.obstacle_index) + " out of range (" +
                         std::to_string(obstacle_count) + " obstacles; -1 for none)");
  }
  if (j.contains("last_confirmed")) {
    tag.last_confirmed = r.String(j["last_confirmed"], path.Key("last_confirmed"));
  }
  return tag;
}

MapObstacle ReadObstacle(const Json& j, const JsonReader& r, const JsonPath& path) {
  r.ExpectObject(j, path, {"kind", "points"});
  MapObstacle obstacle;
  const JsonPath kind_path = path.Key("kind");
  const std::string& kind = r.String(j["kind"], kind_path);
  const std::optional<ObstacleKind> obstacle_kind = ObstacleKindFromString(kind);
  if (!obstacle_kind) r.Fail(kind_path, "expected pillar or wall, got '" + kind + "'");
  obstacle.kind = *obstacle_kind;
  const JsonPath points = path.Key("points");
  r.ExpectArray(j["points"], points);
  const std::size_t min_points = obstacle.kind == ObstacleKind::kPillar ? 3 : 2;
  if (j["points"].size() < min_points) {
    r.Fail(points, "expected at least " + std::to_string(min_points) + " points for a " + kind +
                       ", got " + std::to_string(j["points"].size()));
  }
  for (std::size_t i = 0; i < j["points"].size(); ++i) {
    const JsonPath point = points.Index(i);
    obstacle.points_map.push_back(r.Point(j["points"][i], point, kMaxCoordinate_m, "m"));
  }
  return obstacle;
}

void CheckUniqueSlotIds(const SemanticMap& map, const JsonReader& r, const JsonPath& slots) {
  std::map<std::string, std::size_t> first_index;
  for (std::size_t i = 0; i < map.slots.size(); ++i) {
    const std::string& id = map.slots[i].id;
    if (id.empty()) continue;
    const auto [it, inserted] = first_index.emplace(id, i);
    if (!inserted) {
      const JsonPath slot = slots.Index(i);
      r.Fail(slot.Key("id"),
             "duplicate id '" + id + "' (also slots[" + std::to_string(it->second) + "])");
    }
  }
}

// Two tags of one ID: the localizer would tie every sighting to one of them.
void CheckUniqueTagIds(const SemanticMap& map, const JsonReader& r, const JsonPath& tags) {
  std::map<int, std::size_t> first_index;
  for (std::size_t i = 0; i < map.tags.size(); ++i) {
    const auto [it, inserted] = first_index.emplace(map.tags[i].tag_id, i);
    if (!inserted) {
      r.Fail(tags.Index(i).Key("id"), "duplicate id " + std::to_string(map.tags[i].tag_id) +
                                          " (also tags[" + std::to_string(it->second) + "])");
    }
  }
}

}  // namespace

nlohmann::json MapToJson(const SemanticMap& map) {
  Json slots = Json::array(), tags = Json::array(), obstacles = Json::array();
  for (const MapSlot& slot : map.slots) slots.push_back(SlotJson(slot));
  for (const MapTag& tag : map.tags) tags.push_back(TagJson(tag));
  for (const MapObstacle& obstacle : map.obstacles) {
    obstacles.push_back(ObstacleJson(obstacle));
  }
  Json metadata = Json::object();
  for (const auto& [key, value] : map.metadata) metadata[key] = value;
  Json json{{"format", kMapFormatName},
            {"version", kMapFormatVersion},
            {"frame", "map"},
            {"units", {{"length", "m"}, {"angle", "rad"}}},
            {"metadata", metadata},
            {"slots", slots},
            {"tags", tags},
            {"obstacles", obstacles}};
  if (map.entrance) {
    json["entrance"] = {
        {"x", map.entrance->x()}, {"y", map.entrance->y()}, {"yaw", map.entrance->yaw()}};
  }
  return json;
}

SemanticMap MapFromJson(const nlohmann::json& json, const std::string& source_name) {
  const JsonReader r(source_name, 0);
  const JsonPath root;
  CheckHeader(json, r, root);
  SemanticMap map;
  map.metadata = ReadMetadata(json["metadata"], r, root.Key("metadata"));
  if (json.contains("entrance")) {
    const JsonPath entrance = root.Key("entrance");
    const Json& e = json["entrance"];
    r.ExpectObject(e, entrance, {"x", "y", "yaw"});
    map.entrance = SE2(r.BoundedNumber(e["x"], entrance.Key("x"), kMaxCoordinate_m, "m"),
                       r.BoundedNumber(e["y"], entrance.Key("y"), kMaxCoordinate_m, "m"),
                       r.BoundedNumber(e["yaw"], entrance.Key("yaw"), kMaxAngle_rad, "rad"));
  }

  const JsonPath obstacles = root.Key("obstacles");
  r.ExpectArray(json["obstacles"], obstacles);
  for (std::size_t i = 0; i < json["obstacles"].size(); ++i) {
    const JsonPath obstacle = obstacles.Index(i);
    map.obstacles.push_back(ReadObstacle(json["obstacles"][i], r, obstacle));
  }
  const JsonPath slots = root.Key("slots");
  r.ExpectArray(json["slots"], slots);
  for (std::size_t i = 0; i < json["slots"].size(); ++i) {
    const JsonPath slot = slots.Index(i);
    map.slots.push_back(ReadSlot(json["slots"][i], r, slot));
  }
  CheckUniqueSlotIds(map, r, slots);
  const JsonPath tags = root.Key("tags");
  r.ExpectArray(json["tags"], tags);
  for (std::size_t i = 0; i < json["tags"].size(); ++i) {
    const JsonPath tag = tags.Index(i);
    map.tags.push_back(ReadTag(json["tags"][i], r, tag, map.obstacles.size()));
  }
  CheckUniqueTagIds(map, r, tags);
  return map;
}

void WriteMap(const std::filesystem::path& path, const SemanticMap& map) {
  const Json json = MapToJson(map);
  MapFromJson(json, path.string());  // what does not read back is not written
  WriteFileAtomically(path, json_util::PrettyJson(json, KeyOrder()));
}

SemanticMap ReadMap(const std::filesystem::path& path) {
  const std::string text = ReadTextFile(path, kMaxJsonBytes);
  const Json json = json_util::ParseJson(text, path.string(), 0);
  return MapFromJson(json, path.string());
}

}  // namespace parkslam::io
