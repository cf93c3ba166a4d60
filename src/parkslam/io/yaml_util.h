#ifndef PARKSLAM_IO_YAML_UTIL_H_
#define PARKSLAM_IO_YAML_UTIL_H_

// Internal to io/: strict typed reading of yaml-cpp nodes with key paths in
// every message, and the writing of YAML scalars.

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "parkslam/sim/scenario_config.h"

namespace parkslam::io::yaml_util {

// "world.rows" + "count" -> "world.rows.count"; "" + "world" -> "world".
std::string JoinKey(const std::string& path, std::string_view key);
// "world.rows" + 2 -> "world.rows[2]".
std::string IndexKey(const std::string& path, std::size_t index);

// The most nodes a YAML input may expand to, aliases counted where they are
// used (docs/plausible_ranges.md, "Input sizes"): a plan of 20,000 slots
// has about 400,000.
inline constexpr std::size_t kMaxYamlNodes = 500'000;

// Parses YAML text; throws IoError "source:line:column: invalid YAML: ...",
// or "source: expands to more than ... YAML nodes".
YAML::Node LoadYaml(const std::string& text, const std::string& source);

class YamlReader {
 public:
  // With use_lines, messages carry the line of the offending node
  // ("world.yaml:12: world.hall.min_x_m: ..."); without, only the source.
  YamlReader(std::string source, bool use_lines)
      : source_(std::move(source)), use_lines_(use_lines) {}

  [[noreturn]] void Fail(const YAML::Node& node, const std::string& path,
                         std::string_view what) const;

  double Double(const YAML::Node& node, const std::string& path) const;  // finite
  // Double() with |value| <= max_abs, or within [min, max]: a limit of
  // common/plausible_ranges.h, in `unit` ("m", "px"; "" for none).
  double BoundedDouble(const YAML::Node& node, const std::string& path, double max_abs,
                       std::string_view unit) const;
  double DoubleIn(const YAML::Node& node, const std::string& path, double min, double max,
                  std::string_view unit) const;
  std::int64_t Int64(const YAML::Node& node, const std::string& path) const;
  int Int(const YAML::Node& node, const std::string& path) const;
  std::uint64_t Uint64(const YAML::Node& node, const std::string& path) const;
  bool Bool(const YAML::Node& node, const std::string& path) const;
  std::string String(const YAML::Node& node, const std::string& path) const;
  Eigen::Vector2d Point(const YAML::Node& node, const std::string& path) const;

  void ExpectMap(const YAML::Node& node, const std::string& path) const;
  void ExpectSequence(const YAML::Node& node, const std::string& path) const;
  // Rejects keys of the mapping `node` that are not in `known`, and keys
  // given twice; suggests the closest known key for a misspelt one.
  void CheckKeys(const YAML::Node& node, const std::string& path,
                 const std::vector<std::string_view>& known) const;
  // A mapping with exactly `keys`: CheckKeys, and every key present.
  void ExpectKeys(const YAML::Node& node, const std::string& path,
                  std::initializer_list<std::string_view> keys) const;

 private:
  std::string Scalar(const YAML::Node& node, const std::string& path, const char* expected) const;

  std::string source_;
  bool use_lines_;
};

// Writes a double that reads back exactly, as a YAML float ("0.1", "12",
// "1.0e-05"; ".nan" and ".inf" for non-finite values).
void AppendYamlDouble(std::string* out, double value);
// Writes a double-quoted YAML string.
void AppendYamlString(std::string* out, std::string_view value);

// The scenario under `node` (a mapping) overlaid onto *config; path prefixes
// the key paths in messages. Defined in scenario_yaml.cc.
void ReadScenarioNode(const YamlReader& reader, const YAML::Node& node, const std::string& path,
                      sim::ScenarioConfig* config);
// The scenario as block YAML, every line indented by `indent` spaces.
void AppendScenarioYaml(const sim::ScenarioConfig& config, int indent, std::string* out);

// The vehicle and the odometry sensors' specification of a dataset, every
// field required; written as block YAML at `indent`.
void ReadVehicleNode(const YamlReader& reader, const YAML::Node& node, const std::string& path,
                     VehicleParameters* vehicle);
void AppendVehicleYaml(const VehicleParameters& vehicle, int indent, std::string* out);
void ReadOdometrySpecNode(const YamlReader& reader, const YAML::Node& node, const std::string& path,
                          OdometrySensorSpec* spec);
void AppendOdometrySpecYaml(const OdometrySensorSpec& spec, int indent, std::string* out);

}  // namespace parkslam::io::yaml_util

#endif  // PARKSLAM_IO_YAML_UTIL_H_
