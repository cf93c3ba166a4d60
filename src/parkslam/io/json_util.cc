#include "parkslam/io/json_util.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include "parkslam/common/convex_polygon.h"
#include "parkslam/common/plausible_ranges.h"
#include "parkslam/io/io_error.h"
#include "parkslam/io/text_util.h"

namespace parkslam::io::json_util {
namespace {

constexpr std::size_t kMaxInlineWidth = 100;
constexpr int kMaxInlineDepth = 2;
constexpr int kIndent = 2;

const char* TypeName(const Json& j) {
  switch (j.type()) {
    case Json::value_t::null:
      return "null";
    case Json::value_t::object:
      return "an object";
    case Json::value_t::array:
      return "an array";
    case Json::value_t::string:
      return "a string";
    case Json::value_t::boolean:
      return "a boolean";
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
      return "an integer";
    case Json::value_t::number_float:
      return "a number";
    default:
      return "something else";
  }
}

int Depth(const Json& j) {
  if (!j.is_structured()) return 0;
  int deepest = 0;
  for (const Json& child : j) deepest = std::max(deepest, Depth(child));
  return deepest + 1;
}

// The object's keys: those of key_order first, in that order, then the rest.
std::vector<std::string> OrderedKeys(const Json& object,
                                     const std::vector<std::string>& key_order) {
  std::vector<std::string> keys;
  for (const std::string& key : key_order) {
    if (object.contains(key)) keys.push_back(key);
  }
  for (const auto& item : object.items()) {
    if (std::find(key_order.begin(), key_order.end(), item.key()) == key_order.end()) {
      keys.push_back(item.key());
    }
  }
  return keys;
}

void AppendInline(const Json& j, const std::vector<std::string>& key_order, std::string* out) {
  if (j.is_array()) {
    out->push_back('[');
    for (std::size_t i = 0; i < j.size(); ++i) {
      if (i > 0) out->append(", ");
      AppendInline(j[i], key_order, out);
    }
    out->push_back(']');
  } else if (j.is_object()) {
    out->push_back('{');
    bool first = true;
    for (const std::string& key : OrderedKeys(j, key_order)) {
      if (!first) out->append(", ");
      first = false;
      AppendJsonString(out, key);
      out->append(": ");
      AppendInline(j.at(key), key_order, out);
    }
    out->push_back('}');
  } else {
    out->append(j.dump(-1, ' ', false, Json::error_handler_t::replace));
  }
}

void AppendPretty(const Json& j, int indent, const std::vector<std::string>& key_order,
                  std::string* out) {
  std::string inline_text;
  AppendInline(j, key_order, &inline_text);
  const bool fits = inline_text.size() + static_cast<std::size_t>(indent) <= kMaxInlineWidth;
  if (!j.is_structured() || j.empty() || (indent > 0 && fits && Depth(j) <= kMaxInlineDepth)) {
    out->append(inline_text);
    return;
  }
  const std::string inner(static_cast<std::size_t>(indent + kIndent), ' ');
  out->push_back(j.is_array() ? '[' : '{');
  out->push_back('\n');
  if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) {
      out->append(inner);
      AppendPretty(j[i], indent + kIndent, key_order, out);
      out->append(i + 1 < j.size() ? ",\n" : "\n");
    }
  } else {
    const std::vector<std::string> keys = OrderedKeys(j, key_order);
    for (std::size_t i = 0; i < keys.size(); ++i) {
      out->append(inner);
      AppendJsonString(out, keys[i]);
      out->append(": ");
      AppendPretty(j.at(keys[i]), indent + kIndent, key_order, out);
      out->append(i + 1 < keys.size() ? ",\n" : "\n");
    }
  }
  out->append(static_cast<std::size_t>(indent), ' ');
  out->push_back(j.is_array() ? ']' : '}');
}

// The path of the value the parser stopped at in `text` ("slots[2].corners[1][0]"),
// spelled like JsonPath; "" at the top level. Parses `text` again, following
// keys and array indices, and is only called once parsing has failed.
std::string ErrorPath(std::string_view text) {
  struct Level {
    bool array = false;
    std::size_t index = 0;           // elements read so far, in an array
    std::optional<std::string> key;  // the key whose value is being read
  };
  std::vector<Level> levels;
  const auto element_read = [&levels] {
    if (levels.empty()) return;
    Level& parent = levels.back();
    if (parent.array) {
      ++parent.index;
    } else {
      parent.key.reset();
    }
  };
  const Json::parser_callback_t follow = [&](int /*depth*/, Json::parse_event_t event,
                                             Json& parsed) {
    switch (event) {
      case Json::parse_event_t::object_start:
        levels.push_back({false, 0, std::nullopt});
        break;
      case Json::parse_event_t::array_start:
        levels.push_back({true, 0, std::nullopt});
        break;
      case Json::parse_event_t::key:
        if (!levels.empty()) levels.back().key = parsed.get<std::string>();
        break;
      case Json::parse_event_t::object_end:
      case Json::parse_event_t::array_end:
        if (!levels.empty()) levels.pop_back();
        element_read();
        break;
      case Json::parse_event_t::value:
        element_read();
        break;
    }
    return true;
  };
  // Only the events matter; the parse stops at the same value as before.
  [[maybe_unused]] const Json discarded = Json::parse(text, follow, /*allow_exceptions=*/false);
  std::string path;
  for (const Level& level : levels) {
    if (level.array) {
      path += '[' + std::to_string(level.index) + ']';
    } else if (level.key) {
      if (!path.empty()) path += '.';
      path += *level.key;
    } else {
      break;  // between two keys of an object: the object itself
    }
  }
  return path;
}

}  // namespace

void JsonPath::AppendTo(std::string* out) const {
  if (parent_ == nullptr) return;
  parent_->AppendTo(out);
  if (key_ != nullptr) {
    if (!out->empty()) out->push_back('.');
    out->append(key_);
  } else {
    out->push_back('[');
    out->append(std::to_string(index_));
    out->push_back(']');
  }
}

std::string JsonPath::ToString() const {
  std::string text;
  AppendTo(&text);
  return text;
}

void JsonReader::Fail(const JsonPath& path, std::string_view what) const {
  ThrowIoError(source_, line_, path.ToString(), what);
}

void JsonReader::FailType(const Json& j, const JsonPath& path, const char* expected) const {
  Fail(path, std::string("expected ") + expected + ", got " + TypeName(j));
}

void JsonReader::ExpectObject(const Json& j, const JsonPath& path,
                              std::initializer_list<const char*> keys) const {
  ExpectObject(j, path, keys, {});
}

void JsonReader::ExpectObject(const Json& j, const JsonPath& path,
                              std::initializer_list<const char*> keys,
                              std::initializer_list<const char*> optional_keys) const {
  if (!j.is_object()) FailType(j, path, "an object");
  for (const auto& item : j.items()) {
    const auto is = [&](const char* key) { return item.key() == key; };
    const bool known = std::any_of(keys.begin(), keys.end(), is) ||
                       std::any_of(optional_keys.begin(), optional_keys.end(), is);
    if (!known) Fail(path.Key(item.key().c_str()), "unknown key");
  }
  for (const char* key : keys) {
    if (!j.contains(key)) Fail(path.Key(key), "missing key");
  }
}

void JsonReader::ExpectArray(const Json& j, const JsonPath& path) const {
  if (!j.is_array()) FailType(j, path, "an array");
}

void JsonReader::ExpectArray(const Json& j, const JsonPath& path, std::size_t size,
                             const char* what) const {
  ExpectArray(j, path);
  if (j.size() != size) {
    Fail(path,
         "expected " + std::to_string(size) + " " + what + ", got " + std::to_string(j.size()));
  }
}

double JsonReader::Number(const Json& j, const JsonPath& path) const {
  if (!j.is_number()) FailType(j, path, "a number");
  const double value = j.get<double>();
  if (!std::isfinite(value)) Fail(path, "not a finite number");
  return value;
}

std::int64_t JsonReader::Integer(const Json& j, const JsonPath& path) const {
  if (j.is_number_unsigned()) {
    const auto value = j.get<std::uint64_t>();
    if (value > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
      Fail(path, "integer out of range");
    }
    return static_cast<std::int64_t>(value);
  }
  if (!j.is_number_integer()) FailType(j, path, "an integer");
  return j.get<std::int64_t>();
}

int JsonReader::Int(const Json& j, const JsonPath& path) const {
  const std::int64_t value = Integer(j, path);
  if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max()) {
    Fail(path, "integer out of range");
  }
  return static_cast<int>(value);
}

bool JsonReader::Bool(const Json& j, const JsonPath& path) const {
  if (!j.is_boolean()) FailType(j, path, "a boolean");
  return j.get<bool>();
}

const std::string& JsonReader::String(const Json& j, const JsonPath& path) const {
  if (!j.is_string()) FailType(j, path, "a string");
  return j.get_ref<const std::string&>();
}

double JsonReader::BoundedNumber(const Json& j, const JsonPath& path, double max_abs,
                                 std::string_view unit) const {
  const double value = Number(j, path);
  if (std::abs(value) > max_abs) Fail(path, text::BeyondPlausible(value, max_abs, unit));
  return value;
}

double JsonReader::NumberIn(const Json& j, const JsonPath& path, double min, double max,
                            std::string_view unit) const {
  const double value = Number(j, path);
  if (value < min || value > max) Fail(path, text::OutsidePlausible(value, min, max, unit));
  return value;
}

Eigen::Vector2d JsonReader::Point(const Json& j, const JsonPath& path, double max_abs,
                                  std::string_view unit) const {
  ExpectArray(j, path, 2, "coordinates [x, y]");
  const JsonPath x_path = path.Index(0);
  const JsonPath y_path = path.Index(1);
  return Eigen::Vector2d(BoundedNumber(j[0], x_path, max_abs, unit),
                         BoundedNumber(j[1], y_path, max_abs, unit));
}

namespace {

// What is wrong at byte `at` (0-based) of text that failed to parse, in
// words for the user rather than the parser's.
std::string JsonProblem(std::string_view text, std::size_t at) {
  if (text.size() >= 2 && (text[0] == '\0' || text[1] == '\0' ||
                           (static_cast<unsigned char>(text[0]) >= 0xFE &&
                            static_cast<unsigned char>(text[1]) >= 0xFE))) {
    return "not UTF-8 text (UTF-16?); JSON files are read as UTF-8";
  }
  if (text.find_first_not_of(" \t\r\n") == std::string_view::npos) return "empty: no JSON value";
  if (at >= text.size()) return "ends before its value does (a truncated file?)";
  std::size_t start = at;
  while (start > 0 && std::isalpha(static_cast<unsigned char>(text[start - 1]))) --start;
  const std::string_view word = text.substr(start, 9);
  for (const std::string_view bad : {"NaN", "nan", "Infinity", "-Infinity", "inf"}) {
    if (word.rfind(bad, 0) == 0) {
      return "NaN and Infinity are not JSON numbers; write a finite number";
    }
  }
  const unsigned char c = static_cast<unsigned char>(text[at]);
  if (c < 0x20 || c >= 0x7F) {
    char code[8];
    std::snprintf(code, sizeof(code), "0x%02X", c);
    return std::string("unexpected byte ") + code;
  }
  return std::string("unexpected '") + static_cast<char>(c) + "'";
}

// "line L, column C" of byte `at` in `text`, counted from 1.
std::string LineColumn(std::string_view text, std::size_t at) {
  at = std::min(at, text.size());
  int lines = 1;
  std::size_t line_start = 0;
  for (std::size_t k = 0; k < at; ++k) {
    if (text[k] == '\n') {
      ++lines;
      line_start = k + 1;
    }
  }
  return "line " + std::to_string(lines) + ", column " + std::to_string(at - line_start + 1);
}

}  // namespace

Json ParseJson(std::string_view text, std::string_view source, int line) {
  try {
    return Json::parse(text);
  } catch (const Json::parse_error& e) {
    // nlohmann's byte is 1-based, the last one read.
    const std::size_t at = e.byte > 0 ? e.byte - 1 : 0;
    ThrowIoError(source, line, ErrorPath(text),
                 "invalid JSON: at " + LineColumn(text, at) + ": " + JsonProblem(text, at));
  } catch (const Json::out_of_range& e) {
    // nlohmann names the number in quotes: the user's own text.
    const std::string what = e.what();
    const size_t open = what.find('\'');
    const size_t close = what.rfind('\'');
    const std::string number =
        open != std::string::npos && close > open ? what.substr(open, close - open + 1) : "";
    ThrowIoError(source, line, ErrorPath(text),
                 "invalid JSON: the number " + number + " is beyond the range of a double");
  } catch (const Json::exception&) {
    // Should a later nlohmann throw some other kind here: still an IoError,
    // and still in the project's words.
    ThrowIoError(source, line, ErrorPath(text), "invalid JSON");
  }
}

std::string PrettyJson(const Json& j, const std::vector<std::string>& key_order) {
  std::string out;
  AppendPretty(j, 0, key_order, &out);
  out.push_back('\n');
  return out;
}

void AppendJsonString(std::string* out, std::string_view value) {
  out->append(Json(std::string(value)).dump(-1, ' ', false, Json::error_handler_t::replace));
}

void CheckSlotArea(const std::array<Eigen::Vector2d, 4>& corners, const JsonReader& r,
                   const JsonPath& path) {
  const double area_m2 = PolygonArea({corners.begin(), corners.end()});
  if (area_m2 >= kMinSlotArea_m2) return;
  char what[160];
  std::snprintf(what, sizeof what,
                "the corners enclose %.2f m^2, not a slot (at least %g m^2; the smallest slot "
                "has 2.25)",
                area_m2, kMinSlotArea_m2);
  r.Fail(path, what);
}

}  // namespace parkslam::io::json_util
