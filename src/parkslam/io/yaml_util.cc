#include "parkslam/io/yaml_util.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "parkslam/io/io_error.h"
#include "parkslam/io/text_util.h"

namespace parkslam::io::yaml_util {
namespace {

std::string Describe(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "nothing";
  if (node.IsScalar()) return text::Quoted(node.Scalar());
  if (node.IsSequence()) return "a list";
  return "a mapping";
}

std::size_t EditDistance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::string UnknownKeyMessage(std::string_view key, const std::vector<std::string_view>& known) {
  constexpr std::size_t kMaxTypos = 2;
  std::string_view best;
  std::size_t best_distance = kMaxTypos + 1;
  for (std::string_view candidate : known) {
    const std::size_t distance = EditDistance(key, candidate);
    if (distance < best_distance) {
      best_distance = distance;
      best = candidate;
    }
  }
  std::string message = "unknown key";
  if (!best.empty()) message += " (did you mean '" + std::string(best) + "'?)";
  return message;
}

bool IsSpecialFloat(std::string_view text) {
  static const std::set<std::string_view> kSpecial = {".inf",  ".Inf",  ".INF",  "+.inf",
                                                      "+.Inf", "+.INF", "-.inf", "-.Inf",
                                                      "-.INF", ".nan",  ".NaN",  ".NAN"};
  return kSpecial.count(text) > 0;
}

}  // namespace

std::string JoinKey(const std::string& path, std::string_view key) {
  if (path.empty()) return std::string(key);
  std::string joined = path;
  joined += '.';
  joined += key;
  return joined;
}

std::string IndexKey(const std::string& path, std::size_t index) {
  return path + "[" + std::to_string(index) + "]";
}

namespace {

// The nodes a reader visits in `node`, aliases counted where they are used
// (YAML's "billion laughs": 600 KB of nested aliases made 200,000 slots),
// counted until `budget` runs out.
void CountNodes(const YAML::Node& node, std::size_t* budget) {
  if (*budget == 0) return;
  --*budget;
  if (node.IsSequence()) {
    for (const YAML::Node& child : node) {
      CountNodes(child, budget);
      if (*budget == 0) return;
    }
  } else if (node.IsMap()) {
    for (const auto& pair : node) {
      CountNodes(pair.first, budget);
      CountNodes(pair.second, budget);
      if (*budget == 0) return;
    }
  }
}

}  // namespace

YAML::Node LoadYaml(const std::string& text, const std::string& source) {
  try {
    YAML::Node root = YAML::Load(text);
    std::size_t budget = kMaxYamlNodes + 1;
    CountNodes(root, &budget);
    if (budget == 0) {
      ThrowIoError(source, 0, "",
                   "expands to more than " + std::to_string(kMaxYamlNodes) +
                       " YAML nodes (aliases counted where they are used); not read");
    }
    return root;
  } catch (const YAML::Exception& e) {
    std::string where = source;
    if (e.mark.line >= 0) {
      where += ":" + std::to_string(e.mark.line + 1) + ":" + std::to_string(e.mark.column + 1);
    }
    ThrowIoError(where, 0, "", "invalid YAML: " + e.msg);
  }
}

void YamlReader::Fail(const YAML::Node& node, const std::string& path,
                      std::string_view what) const {
  int line = 0;
  if (use_lines_ && node.IsDefined() && node.Mark().line >= 0) {
    line = node.Mark().line + 1;
  }
  ThrowIoError(source_, line, path, what);
}

std::string YamlReader::Scalar(const YAML::Node& node, const std::string& path,
                               const char* expected) const {
  if (!node.IsDefined() || !node.IsScalar()) {
    Fail(node, path, std::string("expected ") + expected + ", got " + Describe(node));
  }
  return node.Scalar();
}

double YamlReader::Double(const YAML::Node& node, const std::string& path) const {
  const std::string text = Scalar(node, path, "a number");
  const std::optional<double> value = text::ParseDouble(text);
  if (IsSpecialFloat(text) || (value && !std::isfinite(*value))) {
    Fail(node, path, "not a finite number");
  }
  if (!value) Fail(node, path, "expected a number, got " + text::Quoted(text));
  return *value;
}

double YamlReader::BoundedDouble(const YAML::Node& node, const std::string& path, double max_abs,
                                 std::string_view unit) const {
  const double value = Double(node, path);
  if (std::abs(value) > max_abs) Fail(node, path, text::BeyondPlausible(value, max_abs, unit));
  return value;
}

double YamlReader::DoubleIn(const YAML::Node& node, const std::string& path, double min, double max,
                            std::string_view unit) const {
  const double value = Double(node, path);
  if (value < min || value > max) {
    Fail(node, path, text::OutsidePlausible(value, min, max, unit));
  }
  return value;
}

std::int64_t YamlReader::Int64(const YAML::Node& node, const std::string& path) const {
  const std::string text = Scalar(node, path, "an integer");
  const std::optional<std::int64_t> value = text::ParseInt64(text);
  if (!value) Fail(node, path, "expected an integer, got " + text::Quoted(text));
  return *value;
}

int YamlReader::Int(const YAML::Node& node, const std::string& path) const {
  const std::int64_t value = Int64(node, path);
  if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max()) {
    Fail(node, path, "integer out of range");
  }
  return static_cast<int>(value);
}

std::uint64_t YamlReader::Uint64(const YAML::Node& node, const std::string& path) const {
  const std::string text = Scalar(node, path, "a non-negative integer");
  const std::optional<std::uint64_t> value = text::ParseUint64(text);
  if (!value) {
    Fail(node, path, "expected a non-negative integer, got " + text::Quoted(text));
  }
  return *value;
}

bool YamlReader::Bool(const YAML::Node& node, const std::string& path) const {
  const std::string text = Scalar(node, path, "true or false");
  if (text == "true" || text == "True" || text == "TRUE") return true;
  if (text == "false" || text == "False" || text == "FALSE") return false;
  Fail(node, path, "expected true or false, got " + text::Quoted(text));
}

std::string YamlReader::String(const YAML::Node& node, const std::string& path) const {
  return Scalar(node, path, "a string");
}

Eigen::Vector2d YamlReader::Point(const YAML::Node& node, const std::string& path) const {
  if (!node.IsDefined() || !node.IsSequence() || node.size() != 2) {
    Fail(node, path, "expected a point [x, y], got " + Describe(node));
  }
  return Eigen::Vector2d(Double(node[0], IndexKey(path, 0)), Double(node[1], IndexKey(path, 1)));
}

void YamlReader::ExpectMap(const YAML::Node& node, const std::string& path) const {
  if (!node.IsDefined() || !node.IsMap()) {
    Fail(node, path, "expected a mapping of keys, got " + Describe(node));
  }
}

void YamlReader::ExpectSequence(const YAML::Node& node, const std::string& path) const {
  if (!node.IsDefined() || !node.IsSequence()) {
    Fail(node, path, "expected a list, got " + Describe(node));
  }
}

void YamlReader::CheckKeys(const YAML::Node& node, const std::string& path,
                           const std::vector<std::string_view>& known) const {
  std::set<std::string> seen;
  for (auto it = node.begin(); it != node.end(); ++it) {
    const YAML::Node key_node = it->first;
    if (!key_node.IsScalar()) Fail(key_node, path, "keys must be plain names");
    const std::string& key = key_node.Scalar();
    if (std::find(known.begin(), known.end(), key) == known.end()) {
      Fail(key_node, JoinKey(path, key), UnknownKeyMessage(key, known));
    }
    if (!seen.insert(key).second) Fail(key_node, JoinKey(path, key), "key given twice");
  }
}

void YamlReader::ExpectKeys(const YAML::Node& node, const std::string& path,
                            std::initializer_list<std::string_view> keys) const {
  ExpectMap(node, path);
  CheckKeys(node, path, std::vector<std::string_view>(keys));
  for (std::string_view key : keys) {
    if (!node[std::string(key)]) Fail(node, JoinKey(path, key), "missing key");
  }
}

void AppendYamlDouble(std::string* out, double value) {
  if (std::isnan(value)) {
    out->append(".nan");
    return;
  }
  if (std::isinf(value)) {
    out->append(value > 0 ? ".inf" : "-.inf");
    return;
  }
  const std::size_t begin = out->size();
  text::AppendDouble(out, value);
  // YAML 1.1 readers want a '.' in a float with an exponent: 1e-05 -> 1.0e-05.
  const std::size_t exponent = out->find('e', begin);
  if (exponent != std::string::npos && out->find('.', begin) == std::string::npos) {
    out->insert(exponent, ".0");
  }
}

void AppendYamlString(std::string* out, std::string_view value) {
  static constexpr char kHex[] = "0123456789abcdef";
  out->push_back('"');
  for (const char c : value) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out->push_back('\\');
      out->push_back(c);
    } else if (byte < 0x20 || byte == 0x7f) {
      out->append("\\x");
      out->push_back(kHex[byte >> 4]);
      out->push_back(kHex[byte & 0xf]);
    } else {
      out->push_back(c);
    }
  }
  out->push_back('"');
}

}  // namespace parkslam::io::yaml_util
