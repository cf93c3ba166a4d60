#ifndef PARKSLAM_IO_MAP_JSON_H_
#define PARKSLAM_IO_MAP_JSON_H_

// The file format of SemanticMap (JSON):
//
// {
//   "format": "parkslam-map", "version": 1, "frame": "map",
//   "units": {"length": "m", "angle": "rad"},
//   "metadata": {"source": "simulator", ...},            string -> string
//   "slots": [{"id": "38",             painted ID; "t3" temporary; "" none
//              "temporary": false, "id_legible": true,
//              "kind": "perpendicular",  | "angled" | "parallel"
//              "corners": [[x, y], [x, y], [x, y], [x, y]],  0-1 entrance line
//              "corner_observed": [true, true, true, true],
//              "corner_sigma_m": [0.05, 0.05, 0.1, 0.1],
//              "observations": 12}],
//   "tags": [{"id": 7, "x": 3.2, "y": 9.1, "yaw": 1.570796, "size_m": 0.488,
//             "obstacle": 4}],                  index into obstacles, -1 none
//   "obstacles": [{"kind": "pillar",                      | "wall"
//                  "points": [[x, y], ...]}]              polygon / polyline
// }
//
// Coordinates are in the map frame; lengths are written to the millimetre,
// angles and standard deviations to 1e-6. Reading accepts nothing else:
// every key must be present and known, every number finite.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "parkslam/map/semantic_map.h"

namespace parkslam::io {

inline constexpr char kMapFormatName[] = "parkslam-map";
inline constexpr int kMapFormatVersion = 1;

nlohmann::json MapToJson(const SemanticMap& map);

// Throws IoError naming source_name and the JSON path of the first problem:
// wrong format or version, unknown or missing keys, wrong types, non-finite
// numbers, a wrong number of corners, an obstacle index out of range, a
// non-empty slot ID used twice.
SemanticMap MapFromJson(const nlohmann::json& json, const std::string& source_name);

// Writes atomically, indented. Throws IoError, before writing anything, when
// the map would not read back (a NaN, a duplicate ID, a bad obstacle index).
void WriteMap(const std::filesystem::path& path, const SemanticMap& map);

SemanticMap ReadMap(const std::filesystem::path& path);

}  // namespace parkslam::io

#endif  // PARKSLAM_IO_MAP_JSON_H_
