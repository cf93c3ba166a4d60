#include "parkslam/io/text_util.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <system_error>

#include "parkslam/io/io_error.h"

namespace parkslam::io::text {
namespace {

// A leading '+' is valid in our files but not for std::from_chars.
std::string_view StripPlus(std::string_view text) {
  if (text.size() > 1 && text.front() == '+' && text[1] != '-' && text[1] != '+') {
    text.remove_prefix(1);
  }
  return text;
}

template <typename T>
std::optional<T> ParseWhole(std::string_view text) {
  text = StripPlus(text);
  if (text.empty()) return std::nullopt;
  T value{};
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || ptr != end) return std::nullopt;
  return value;
}

// A limit as people write it: "100000", "0.01", "1e-15" (6 significant
// digits; the value beside it is exact).
std::string Limit(double limit) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", limit);
  return buffer;
}

std::string WithUnit(std::string text, std::string_view unit) {
  if (!unit.empty()) {
    text.push_back(' ');
    text.append(unit);
  }
  return text;
}

}  // namespace

void AppendDouble(std::string* out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out->append(buffer, result.ptr);
}

void AppendFixed(std::string* out, double value, int decimals) {
  char buffer[64];
  auto result =
      std::to_chars(buffer, buffer + sizeof(buffer), value, std::chars_format::fixed, decimals);
  if (result.ec != std::errc()) {  // |value| too large for the buffer
    result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  }
  out->append(buffer, result.ptr);
}

void AppendInteger(std::string* out, std::int64_t value) {
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out->append(buffer, result.ptr);
}

std::optional<double> ParseDouble(std::string_view text) {
  // std::from_chars also reads "inf" and "nan"; callers reject them.
  return ParseWhole<double>(text);
}

std::optional<std::int64_t> ParseInt64(std::string_view text) {
  return ParseWhole<std::int64_t>(text);
}

std::optional<std::uint64_t> ParseUint64(std::string_view text) {
  return ParseWhole<std::uint64_t>(text);
}

double ParseFiniteDouble(std::string_view text, std::string_view file, int line,
                         std::string_view field) {
  const std::optional<double> value = ParseDouble(text);
  if (!value) ThrowIoError(file, line, field, "not a number " + Quoted(text));
  if (!std::isfinite(*value)) ThrowIoError(file, line, field, "not a finite number");
  return *value;
}

std::string Quoted(std::string_view text) {
  constexpr std::size_t kMaxShown = 40;
  std::string quoted = "'";
  quoted.append(text.substr(0, kMaxShown));
  if (text.size() > kMaxShown) quoted.append("...");
  quoted.push_back('\'');
  return quoted;
}

std::string BeyondPlausible(double value, double max_abs, std::string_view unit) {
  std::string message;
  AppendDouble(&message, value);
  return WithUnit(message + " is beyond the plausible " + Limit(max_abs), unit);
}

std::string OutsidePlausible(double value, double min, double max, std::string_view unit) {
  std::string message;
  AppendDouble(&message, value);
  return WithUnit(
      message + " is outside the plausible range [" + Limit(min) + ", " + Limit(max) + "]", unit);
}

std::string_view Trim(std::string_view text) {
  constexpr std::string_view kSpace = " \t\r\n";
  const std::size_t begin = text.find_first_not_of(kSpace);
  if (begin == std::string_view::npos) return {};
  const std::size_t end = text.find_last_not_of(kSpace);
  return text.substr(begin, end - begin + 1);
}

bool LineCursor::Next(std::string_view* line) {
  if (done_ || rest_.empty()) {
    done_ = true;
    return false;
  }
  ++line_number_;
  const std::size_t newline = rest_.find('\n');
  if (newline == std::string_view::npos) {
    *line = rest_;
    done_ = true;
  } else {
    *line = rest_.substr(0, newline);
    rest_.remove_prefix(newline + 1);
  }
  if (!line->empty() && line->back() == '\r') line->remove_suffix(1);
  return true;
}

std::size_t Split(std::string_view line, char separator, std::string_view* fields,
                  std::size_t max_fields) {
  std::size_t count = 0;
  while (true) {
    const std::size_t next = line.find(separator);
    if (count < max_fields) fields[count] = line.substr(0, next);
    ++count;
    if (next == std::string_view::npos) return count;
    line.remove_prefix(next + 1);
  }
}

}  // namespace parkslam::io::text
