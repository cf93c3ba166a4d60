#ifndef PARKSLAM_IO_JSON_UTIL_H_
#define PARKSLAM_IO_JSON_UTIL_H_

// Internal to io/: strict reading of parsed JSON with error paths, and a
// compact pretty printer.

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace parkslam::io::json_util {

using Json = nlohmann::json;

// A place inside a JSON document ("slots[3].corners[1]"), chained on the
// stack and spelled out only when an error is reported. A path refers to its
// parent, so give every level its own named variable:
//   const JsonPath slots = root.Key("slots");
//   const JsonPath slot = slots.Index(i);
class JsonPath {
 public:
  JsonPath() = default;
  JsonPath Key(const char* key) const { return JsonPath(this, key, 0); }
  JsonPath Index(std::size_t index) const { return JsonPath(this, nullptr, index); }
  std::string ToString() const;

 private:
  JsonPath(const JsonPath* parent, const char* key, std::size_t index)
      : parent_(parent), key_(key), index_(index) {}
  void AppendTo(std::string* out) const;

  const JsonPath* parent_ = nullptr;
  const char* key_ = nullptr;  // null for an array element
  std::size_t index_ = 0;
};

// Typed access to a parsed document that accepts nothing unexpected. Every
// failure throws IoError "source[:line]: path: what".
class JsonReader {
 public:
  // line <= 0 leaves the line out of messages.
  JsonReader(std::string_view source, int line) : source_(source), line_(line) {}

  [[noreturn]] void Fail(const JsonPath& path, std::string_view what) const;

  // `j` must be an object with exactly `keys`, no more and no fewer.
  void ExpectObject(const Json& j, const JsonPath& path,
                    std::initializer_list<const char*> keys) const;
  // The same, with keys that may also be left out.
  void ExpectObject(const Json& j, const JsonPath& path, std::initializer_list<const char*> keys,
                    std::initializer_list<const char*> optional_keys) const;
  void ExpectArray(const Json& j, const JsonPath& path) const;
  // An array of exactly `size` elements; `what` names them ("points").
  void ExpectArray(const Json& j, const JsonPath& path, std::size_t size, const char* what) const;

  double Number(const Json& j, const JsonPath& path) const;  // finite
  std::int64_t Integer(const Json& j, const JsonPath& path) const;
  int Int(const Json& j, const JsonPath& path) const;
  bool Bool(const Json& j, const JsonPath& path) const;
  const std::string& String(const Json& j, const JsonPath& path) const;

  // Number() with |value| <= max_abs, or within [min, max]: a limit of
  // common/plausible_ranges.h, in `unit` ("m", "rad"; "" for none).
  double BoundedNumber(const Json& j, const JsonPath& path, double max_abs,
                       std::string_view unit) const;
  double NumberIn(const Json& j, const JsonPath& path, double min, double max,
                  std::string_view unit) const;
  // [x, y], both coordinates bounded as BoundedNumber().
  Eigen::Vector2d Point(const Json& j, const JsonPath& path, double max_abs,
                        std::string_view unit) const;

 private:
  [[noreturn]] void FailType(const Json& j, const JsonPath& path, const char* expected) const;

  std::string_view source_;
  int line_;
};

// A slot's four corners (a map's or an observation's) must enclose at least
// kMinSlotArea_m2 (shoelace formula, either winding); four points on a line,
// on one spot or crossed over are not a slot. Fails naming `corners`.
void CheckSlotArea(const std::array<Eigen::Vector2d, 4>& corners, const JsonReader& r,
                   const JsonPath& path);

// Json::parse that throws nothing but IoError "source[:line]: invalid JSON: ...".
// nlohmann reports a syntax error as parse_error, whose message gives the
// position, but a number beyond the range of a double (1e999) as
// out_of_range, with no position: then the message names the path of the
// value instead ("source: tags[0].x: invalid JSON: ... '1e999'").
Json ParseJson(std::string_view text, std::string_view source, int line);

// Indented JSON text that keeps small arrays and objects on one line. Object
// keys listed in `key_order` come first, in that order, the others after
// them in sorted order.
std::string PrettyJson(const Json& j, const std::vector<std::string>& key_order);

// Appends `value` as a JSON string literal.
void AppendJsonString(std::string* out, std::string_view value);

}  // namespace parkslam::io::json_util

#endif  // PARKSLAM_IO_JSON_UTIL_H_
