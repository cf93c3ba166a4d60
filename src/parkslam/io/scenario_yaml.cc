#include "parkslam/io/scenario_yaml.h"

#include <cstddef>
#include <optional>
#include <string_view>
#include <type_traits>
#include <vector>

#include "parkslam/io/atomic_file.h"
#include "parkslam/io/io_error.h"
#include "parkslam/io/options_yaml.h"
#include "parkslam/io/text_util.h"
#include "parkslam/io/yaml_util.h"

namespace parkslam::io {
namespace {

using yaml_util::IndexKey;
using yaml_util::JoinKey;
using yaml_util::YamlReader;

constexpr std::size_t kMaxFlowWidth = 100;
constexpr int kIndent = 2;

struct NullVisitor {
  template <typename T>
  void operator()(const char*, T&) {}
};

// A struct with a VisitFields() field list (scenario_config.h).
template <typename T>
concept Visitable = requires(T& value, NullVisitor& visitor) {
  value.VisitFields(visitor);
};

template <typename T>
inline constexpr bool kIsVector = false;
template <typename T>
inline constexpr bool kIsVector<std::vector<T>> = true;

// Fields written as one YAML scalar or one short flow list.
template <typename T>
inline constexpr bool kIsScalar =
    std::is_same_v<T, double> || std::is_same_v<T, float> || std::is_same_v<T, int> ||
    std::is_same_v<T, bool> || std::is_same_v<T, std::string> ||
    std::is_same_v<T, Eigen::Vector2d> || std::is_same_v<T, std::vector<double>>;

// ---------------------------------------------------------------------------
// Reading. All overloads are declared before the templates that call them.

void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path,
               double* value) {
  *value = r.Double(node, path);
}
void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path, float* value) {
  *value = static_cast<float>(r.BoundedDouble(node, path, 1e30, ""));
}
void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path,
               std::vector<double>* values) {
  r.ExpectSequence(node, path);
  std::vector<double> read;
  for (std::size_t i = 0; i < node.size(); ++i)
    read.push_back(r.Double(node[i], IndexKey(path, i)));
  *values = std::move(read);
}
void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path, int* value) {
  *value = r.Int(node, path);
}
void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path, bool* value) {
  *value = r.Bool(node, path);
}
void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path,
               std::string* value) {
  *value = r.String(node, path);
}
void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path,
               Eigen::Vector2d* value) {
  *value = r.Point(node, path);
}
void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path,
               std::vector<Eigen::Vector2d>* points) {
  r.ExpectSequence(node, path);
  std::vector<Eigen::Vector2d> read;
  for (std::size_t i = 0; i < node.size(); ++i) {
    read.push_back(r.Point(node[i], IndexKey(path, i)));
  }
  *points = std::move(read);
}
template <Visitable T>
void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path, T* value);
template <Visitable T>
void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path,
               std::vector<T>* values);

// Reads the keys of one mapping into the fields of the struct visiting it.
class FieldReader {
 public:
  FieldReader(const YamlReader& reader, const YAML::Node& node, const std::string& path)
      : reader_(reader), node_(node), path_(path) {}

  template <typename T>
  void operator()(const char* key, T& field) {
    known_.push_back(key);
    const YAML::Node child = node_[key];
    if (child.IsDefined()) ReadValue(reader_, child, JoinKey(path_, key), &field);
  }

  const std::vector<std::string_view>& known() const { return known_; }

 private:
  const YamlReader& reader_;
  const YAML::Node& node_;
  const std::string& path_;
  std::vector<std::string_view> known_;
};

template <Visitable T>
void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path, T* value) {
  r.ExpectMap(node, path);
  FieldReader reader(r, node, path);
  T overlaid = *value;
  overlaid.VisitFields(reader);
  r.CheckKeys(node, path, reader.known());
  *value = std::move(overlaid);
}

template <Visitable T>
void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path,
               std::vector<T>* values) {
  r.ExpectSequence(node, path);
  std::vector<T> read(node.size());  // each element starts from the defaults
  for (std::size_t i = 0; i < node.size(); ++i) {
    ReadValue(r, node[i], IndexKey(path, i), &read[i]);
  }
  *values = std::move(read);
}

// ---------------------------------------------------------------------------
// Writing.

void AppendScalar(std::string* out, double value) { yaml_util::AppendYamlDouble(out, value); }
void AppendScalar(std::string* out, float value) {
  yaml_util::AppendYamlDouble(out, static_cast<double>(value));
}
void AppendScalar(std::string* out, int value) { out->append(std::to_string(value)); }
void AppendScalar(std::string* out, bool value) { out->append(value ? "true" : "false"); }
void AppendScalar(std::string* out, const std::string& value) {
  yaml_util::AppendYamlString(out, value);
}
void AppendScalar(std::string* out, const std::vector<double>& values) {
  out->push_back('[');
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i > 0) out->append(", ");
    yaml_util::AppendYamlDouble(out, values[i]);
  }
  out->push_back(']');
}
void AppendScalar(std::string* out, const Eigen::Vector2d& p) {
  out->push_back('[');
  yaml_util::AppendYamlDouble(out, p.x());
  out->append(", ");
  yaml_util::AppendYamlDouble(out, p.y());
  out->push_back(']');
}

// "{key: value, ...}" of a struct whose fields are all scalars.
class FlowWriter {
 public:
  template <typename T>
  void operator()(const char* key, T& field) {
    if constexpr (kIsScalar<T>) {
      text_.append(text_.size() > 1 ? ", " : "");
      text_.append(key);
      text_.append(": ");
      AppendScalar(&text_, field);
    } else {
      flowable_ = false;
    }
  }
  // The flow text, or nothing when some field is not a scalar.
  std::optional<std::string> Finish() {
    if (!flowable_) return std::nullopt;
    return text_ + "}";
  }

 private:
  std::string text_ = "{";
  bool flowable_ = true;
};

template <Visitable T>
std::optional<std::string> FlowText(T& value, std::size_t available) {
  FlowWriter writer;
  value.VisitFields(writer);
  std::optional<std::string> text = writer.Finish();
  if (text && text->size() > available) return std::nullopt;
  return text;
}

std::size_t Available(int indent, std::string_view key) {
  const std::size_t used = static_cast<std::size_t>(indent) + key.size() + 2;
  return used < kMaxFlowWidth ? kMaxFlowWidth - used : 0;
}

void WriteFields(auto& value, int indent, std::string* out);

// Writes ":" and the value of a field whose "key" is already written.
template <typename T>
void WriteValue(T& value, std::string_view key, int indent, std::string* out) {
  if constexpr (kIsScalar<T>) {
    out->push_back(' ');
    AppendScalar(out, value);
    out->push_back('\n');
  } else if constexpr (std::is_same_v<T, std::vector<Eigen::Vector2d>>) {
    std::string flow = "[";
    for (const Eigen::Vector2d& p : value) {
      flow.append(flow.size() > 1 ? ", " : "");
      AppendScalar(&flow, p);
    }
    flow.push_back(']');
    if (flow.size() <= Available(indent, key)) {
      *out += " " + flow + "\n";
      return;
    }
    out->push_back('\n');
    for (const Eigen::Vector2d& p : value) {
      out->append(static_cast<std::size_t>(indent + kIndent), ' ');
      out->append("- ");
      AppendScalar(out, p);
      out->push_back('\n');
    }
  } else if constexpr (kIsVector<T>) {
    if (value.empty()) {
      out->append(" []\n");
      return;
    }
    out->push_back('\n');
    const int item_indent = indent + kIndent;
    for (auto& element : value) {
      const std::string dash = std::string(static_cast<std::size_t>(item_indent), ' ') + "- ";
      if (auto flow = FlowText(element, Available(item_indent, ""))) {
        *out += dash + *flow + "\n";
        continue;
      }
      std::string block;
      WriteFields(element, item_indent + kIndent, &block);
      block.replace(0, dash.size(), dash);
      out->append(block);
    }
  } else {
    if (auto flow = FlowText(value, Available(indent, key))) {
      *out += " " + *flow + "\n";
      return;
    }
    out->push_back('\n');
    WriteFields(value, indent + kIndent, out);
  }
}

// Writes every field of a struct as "key: value" lines at `indent`.
class FieldWriter {
 public:
  FieldWriter(int indent, std::string* out) : indent_(indent), out_(out) {}

  template <typename T>
  void operator()(const char* key, T& field) {
    out_->append(static_cast<std::size_t>(indent_), ' ');
    out_->append(key);
    out_->push_back(':');
    WriteValue(field, key, indent_, out_);
  }

 private:
  int indent_;
  std::string* out_;
};

void WriteFields(auto& value, int indent, std::string* out) {
  FieldWriter writer(indent, out);
  value.VisitFields(writer);
}

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
    if constexpr (kIsVector<T>) {
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
      ScenarioFromYaml(ReadTextFile(path), sim::DefaultScenario(), path.string());
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

std::string OptionsToYaml(const pipeline::AlgorithmOptions& options) {
  std::string out =
      "# parkslam algorithm options (--config FILE.yaml): front end, mapper, localizer,\n"
      "# follower. Give only the keys you change; units are in the key names.\n";
  pipeline::AlgorithmOptions copy = options;  // VisitFields() is not const
  WriteFields(copy, 0, &out);
  return out;
}

pipeline::AlgorithmOptions OptionsFromYaml(const std::string& yaml_text,
                                           const pipeline::AlgorithmOptions& base,
                                           const std::string& source_name) {
  const YAML::Node root = yaml_util::LoadYaml(yaml_text, source_name);
  pipeline::AlgorithmOptions options = base;
  if (!root.IsNull()) ReadValue(YamlReader(source_name, true), root, "", &options);
  std::string error;
  if (!options.IsValid(&error)) ThrowIoError(source_name, 0, "", error);
  return options;
}

pipeline::AlgorithmOptions LoadOptionsFile(const std::filesystem::path& path) {
  return OptionsFromYaml(ReadTextFile(path), pipeline::AlgorithmOptions{}, path.string());
}

}  // namespace parkslam::io
