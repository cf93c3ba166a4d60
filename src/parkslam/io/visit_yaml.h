#ifndef PARKSLAM_IO_VISIT_YAML_H_
#define PARKSLAM_IO_VISIT_YAML_H_

// Internal to io/: reading and writing any struct that lists its fields
// (VisitFields) as YAML, strictly: unknown keys are errors with a
// suggestion, values are checked as they are read. Shared by the scenario
// files (scenario_yaml.cc) and the algorithm options (options_yaml.cc).

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "parkslam/common/enum_names.h"
#include "parkslam/io/yaml_util.h"

namespace parkslam::io::visit_yaml {

using yaml_util::IndexKey;
using yaml_util::JoinKey;
using yaml_util::YamlReader;

inline constexpr std::size_t kMaxFlowWidth = 100;
inline constexpr int kIndent = 2;

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
inline constexpr bool kIsOptional = false;
template <typename T>
inline constexpr bool kIsOptional<std::optional<T>> = true;

template <typename T>
inline constexpr bool kIsVector = false;
template <typename T>
inline constexpr bool kIsVector<std::vector<T>> = true;

// An enum field is written as one of its names (common/enum_names.h;
// perception::EnumNames(DetectorKind) is one table).
using parkslam::NamedEnum;

// Fields written as one YAML scalar or one short flow list.
template <typename T>
inline constexpr bool kIsScalar =
    std::is_same_v<T, double> || std::is_same_v<T, float> || std::is_same_v<T, int> ||
    std::is_same_v<T, bool> || std::is_same_v<T, std::string> ||
    std::is_same_v<T, Eigen::Vector2d> || std::is_same_v<T, std::vector<double>> || NamedEnum<T>;

// ---------------------------------------------------------------------------
// Reading. All overloads are declared before the templates that call them.

inline void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path,
                      double* value) {
  *value = r.Double(node, path);
}
inline void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path,
                      float* value) {
  *value = static_cast<float>(r.BoundedDouble(node, path, 1e30, ""));
}
inline void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path,
                      std::vector<double>* values) {
  r.ExpectSequence(node, path);
  std::vector<double> read;
  for (std::size_t i = 0; i < node.size(); ++i)
    read.push_back(r.Double(node[i], IndexKey(path, i)));
  *values = std::move(read);
}
inline void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path,
                      int* value) {
  *value = r.Int(node, path);
}
inline void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path,
                      bool* value) {
  *value = r.Bool(node, path);
}
inline void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path,
                      std::string* value) {
  *value = r.String(node, path);
}
inline void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path,
                      Eigen::Vector2d* value) {
  *value = r.Point(node, path);
}
inline void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path,
                      std::vector<Eigen::Vector2d>* points) {
  r.ExpectSequence(node, path);
  std::vector<Eigen::Vector2d> read;
  for (std::size_t i = 0; i < node.size(); ++i) {
    read.push_back(r.Point(node[i], IndexKey(path, i)));
  }
  *points = std::move(read);
}
template <NamedEnum E>
inline void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path,
                      E* value) {
  const std::string name = r.String(node, path);
  const std::optional<E> known = EnumFromName<E>(name);
  if (!known) r.Fail(node, path, "'" + name + "' is none of " + EnumNamesJoined<E>());
  *value = *known;
}
template <Visitable T>
inline void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path,
                      T* value);
template <Visitable T>
inline void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path,
                      std::vector<T>* values);
// An optional field given in the file: read over its value, or over T's
// defaults when it had none.
template <typename T>
inline void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path,
                      std::optional<T>* value) {
  T read = value->has_value() ? **value : T{};
  ReadValue(r, node, path, &read);
  *value = std::move(read);
}

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
inline void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path,
                      T* value) {
  r.ExpectMap(node, path);
  FieldReader reader(r, node, path);
  T overlaid = *value;
  overlaid.VisitFields(reader);
  r.CheckKeys(node, path, reader.known());
  *value = std::move(overlaid);
}

template <Visitable T>
inline void ReadValue(const YamlReader& r, const YAML::Node& node, const std::string& path,
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

inline void AppendScalar(std::string* out, double value) {
  yaml_util::AppendYamlDouble(out, value);
}
inline void AppendScalar(std::string* out, float value) {
  yaml_util::AppendYamlDouble(out, static_cast<double>(value));
}
inline void AppendScalar(std::string* out, int value) { out->append(std::to_string(value)); }
inline void AppendScalar(std::string* out, bool value) { out->append(value ? "true" : "false"); }
inline void AppendScalar(std::string* out, const std::string& value) {
  yaml_util::AppendYamlString(out, value);
}
inline void AppendScalar(std::string* out, const std::vector<double>& values) {
  out->push_back('[');
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i > 0) out->append(", ");
    yaml_util::AppendYamlDouble(out, values[i]);
  }
  out->push_back(']');
}
template <NamedEnum E>
inline void AppendScalar(std::string* out, E value) {
  out->append(EnumName(value));
}
inline void AppendScalar(std::string* out, const Eigen::Vector2d& p) {
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
    if constexpr (kIsOptional<T>) {
      if (field) flowable_ = false;  // an optional field unset is not written
    } else if constexpr (kIsScalar<T>) {
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

inline std::size_t Available(int indent, std::string_view key) {
  const std::size_t used = static_cast<std::size_t>(indent) + key.size() + 2;
  return used < kMaxFlowWidth ? kMaxFlowWidth - used : 0;
}

inline void WriteFields(auto& value, int indent, std::string* out);

// Writes ":" and the value of a field whose "key" is already written.
template <typename T>
inline void WriteValue(T& value, std::string_view key, int indent, std::string* out) {
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
    if constexpr (kIsOptional<T>) {
      if (field) (*this)(key, *field);  // an optional field unset is not written
    } else {
      out_->append(static_cast<std::size_t>(indent_), ' ');
      out_->append(key);
      out_->push_back(':');
      WriteValue(field, key, indent_, out_);
    }
  }

 private:
  int indent_;
  std::string* out_;
};

inline void WriteFields(auto& value, int indent, std::string* out) {
  FieldWriter writer(indent, out);
  value.VisitFields(writer);
}

}  // namespace parkslam::io::visit_yaml

#endif  // PARKSLAM_IO_VISIT_YAML_H_
