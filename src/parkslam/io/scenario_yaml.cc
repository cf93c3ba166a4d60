#include "parkslam/io/scenario_yaml.h"

#include <cstddef>
#include <optional>
#include <string_view>
#include <type_traits>
#include <vector>

#include "parkslam/io/atomic_file.h"
#include "parkslam/io/io_error.h"
#include "parkslam/io/text_util.h"
#include "parkslam/io/visit_yaml.h"
#include "parkslam/io/yaml_util.h"

namespace parkslam::io {
namespace {

using visit_yaml::kIsOptional;
using visit_yaml::kIsVector;
using visit_yaml::ReadValue;
using visit_yaml::Visitable;
using visit_yaml::WriteFields;
using yaml_util::IndexKey;
using yaml_util::JoinKey;
using yaml_util::YamlReader;

// ---------------------------------------------------------------------------
// Command-line overrides.

// One step of a key path: a field name, or an index into a list.
struct PathStep {
  std::string name;
  std::optional<std::size_t> index;
};

// "world.rows[1].count" -> world, rows, [1], count; nothing when malformed.
std::optional<std::vector<PathStep>> ParseKeyPath(std::string_view key) {
  std::vector<PathStep> steps;
  std::size_t i = 0;
  while (i <= key.size()) {
    const std::size_t end = key.find_first_of(".[", i);
    const std::string_view name = key.substr(i, end - i);
    if (name.empty()) return std::nullopt;
    steps.push_back({std::string(name), std::nullopt});
    i = end;
    while (i < key.size() && key[i] == '[') {
      const std::size_t close = key.find(']', i);
      if (close == std::string_view::npos) return std::nullopt;
      const std::optional<std::uint64_t> index =
          text::ParseUint64(key.substr(i + 1, close - i - 1));
      if (!index) return std::nullopt;
      steps.push_back({"", static_cast<std::size_t>(*index)});
      i = close + 1;
    }
    if (i == std::string_view::npos || i >= key.size()) break;
    if (key[i] != '.') return std::nullopt;
    ++i;
  }
  return steps;
}

class Overrider {
 public:
  Overrider(const std::string& key, const std::vector<PathStep>& steps, const YAML::Node& value)
      : reader_("--set", false), key_(key), steps_(steps), value_(value) {}

  template <typename T>
  void Apply(T& field, std::size_t step, const std::string& path) const {
    if (step == steps_.size()) {
      ReadValue(reader_, value_, path, &field);
      return;
    }
    const PathStep& next = steps_[step];
    if constexpr (kIsOptional<T>) {
      if (!field) throw IoError("--set: " + path + ": not set, so none of its keys can be set");
      Apply(*field, step, path);
    } else if constexpr (kIsVector<T>) {
      if (!next.index) Unknown();
      if (*next.index >= field.size()) {
        throw IoError("--set: " + IndexKey(path, *next.index) +
                      ": index out of range (the list has " + std::to_string(field.size()) +
                      " elements)");
      }
      Apply(field[*next.index], step + 1, IndexKey(path, *next.index));
    } else if constexpr (Visitable<T>) {
      if (next.index) Unknown();
      bool found = false;
      auto visitor = [&](const char* name, auto& child) {
        if (found || next.name != name) return;
        found = true;
        Apply(child, step + 1, JoinKey(path, name));
      };
      field.VisitFields(visitor);
      if (!found) Unknown();
    } else {
      Unknown();
    }
  }

 private:
  [[noreturn]] void Unknown() const { throw IoError("--set: unknown key '" + key_ + "'"); }

  YamlReader reader_;
  const std::string& key_;
  const std::vector<PathStep>& steps_;
  const YAML::Node& value_;
};

}  // namespace

namespace yaml_util {

void ReadScenarioNode(const YamlReader& reader, const YAML::Node& node, const std::string& path,
                      sim::ScenarioConfig* config) {
  ReadValue(reader, node, path, config);
}

void AppendScenarioYaml(const sim::ScenarioConfig& config, int indent, std::string* out) {
  sim::ScenarioConfig copy = config;  // VisitFields() is not const
  WriteFields(copy, indent, out);
}

namespace {

// ReadValue, with every field of T required (a recording's datasheet leaves
// nothing to a default).
template <typename T>
void ReadEveryField(const YamlReader& reader, const YAML::Node& node, const std::string& path,
                    T* value) {
  reader.ExpectMap(node, path);
  auto require = [&](const char* name, auto&) {
    if (!node[name]) reader.Fail(node, JoinKey(path, name), "missing key");
  };
  value->VisitFields(require);
  ReadValue(reader, node, path, value);
}

}  // namespace

void ReadVehicleNode(const YamlReader& reader, const YAML::Node& node, const std::string& path,
                     VehicleParameters* vehicle) {
  ReadEveryField(reader, node, path, vehicle);
}

void AppendVehicleYaml(const VehicleParameters& vehicle, int indent, std::string* out) {
  VehicleParameters copy = vehicle;
  WriteFields(copy, indent, out);
}

void ReadOdometrySpecNode(const YamlReader& reader, const YAML::Node& node, const std::string& path,
                          OdometrySensorSpec* spec) {
  ReadEveryField(reader, node, path, spec);
}

void AppendOdometrySpecYaml(const OdometrySensorSpec& spec, int indent, std::string* out) {
  OdometrySensorSpec copy = spec;
  WriteFields(copy, indent, out);
}

}  // namespace yaml_util

std::string ScenarioToYaml(const sim::ScenarioConfig& config) {
  std::string out =
      "# parkslam scenario: world, route, vehicle, sensors. Units are in the\n"
      "# key names (_m metres, _deg degrees, _rad radians, _hz, _kmh ...).\n";
  yaml_util::AppendScenarioYaml(config, 0, &out);
  return out;
}

sim::ScenarioConfig ScenarioFromYaml(const std::string& yaml_text, const sim::ScenarioConfig& base,
                                     const std::string& source_name) {
  const YAML::Node root = yaml_util::LoadYaml(yaml_text, source_name);
  sim::ScenarioConfig config = base;
  if (root.IsNull()) return config;  // an empty file changes nothing
  const YamlReader reader(source_name, true);
  ReadValue(reader, root, "", &config);
  return config;
}

sim::ScenarioConfig LoadScenarioFile(const std::filesystem::path& path) {
  const sim::ScenarioConfig config =
      ScenarioFromYaml(ReadTextFile(path, kMaxYamlBytes), sim::DefaultScenario(), path.string());
  std::string error;
  if (!config.IsValid(&error)) ThrowIoError(path.string(), 0, "", error);
  return config;
}

void ApplyOverride(sim::ScenarioConfig* config, const std::string& assignment) {
  const std::size_t equals = assignment.find('=');
  if (equals == std::string::npos) {
    throw IoError("--set: expected key=value, got " + text::Quoted(assignment));
  }
  const std::string key(text::Trim(std::string_view(assignment).substr(0, equals)));
  const std::string value_text(text::Trim(std::string_view(assignment).substr(equals + 1)));
  const std::optional<std::vector<PathStep>> steps = ParseKeyPath(key);
  if (!steps) throw IoError("--set: unknown key '" + key + "'");
  YAML::Node value;
  try {
    value = YAML::Load(value_text);
  } catch (const YAML::Exception& e) {
    throw IoError("--set: " + key + ": cannot read value " + text::Quoted(value_text) + ": " +
                  e.msg);
  }
  sim::ScenarioConfig updated = *config;
  Overrider(key, *steps, value).Apply(updated, 0, "");
  *config = std::move(updated);
}

}  // namespace parkslam::io
