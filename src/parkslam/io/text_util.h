#ifndef PARKSLAM_IO_TEXT_UTIL_H_
#define PARKSLAM_IO_TEXT_UTIL_H_

// Internal to io/: fast number formatting and strict parsing, line splitting.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace parkslam::io::text {

// Appends the shortest decimal text that reads back as exactly `value`
// ("0.1", "12", "1.5e-07"); non-finite values as "nan", "inf", "-inf".
void AppendDouble(std::string* out, double value);
// Appends `value` in fixed-point notation with `decimals` digits after the
// point ("12.500000").
void AppendFixed(std::string* out, double value, int decimals);
void AppendInteger(std::string* out, std::int64_t value);

// Parse the whole of `text` (a leading '+' allowed, no spaces); nullopt when
// it is not such a number. ParseDouble may return an infinity or a NaN.
std::optional<double> ParseDouble(std::string_view text);
std::optional<std::int64_t> ParseInt64(std::string_view text);
std::optional<std::uint64_t> ParseUint64(std::string_view text);

// ParseDouble that throws IoError naming file, line and field:
// "not a number 'abc'" or "not a finite number".
double ParseFiniteDouble(std::string_view text, std::string_view file, int line,
                         std::string_view field);

// `text` in single quotes for messages, shortened when long.
std::string Quoted(std::string_view text);

// The messages for a value beyond a limit of common/plausible_ranges.h, the
// value exact and the limit readable, `unit` after it ("" for none):
//   "1e+308 is beyond the plausible 100000 m"        (a limit on |value|)
//   "-2 is outside the plausible range [0, 10] m"
std::string BeyondPlausible(double value, double max_abs, std::string_view unit);
std::string OutsidePlausible(double value, double min, double max, std::string_view unit);

std::string_view Trim(std::string_view text);

// Walks the lines of a text, numbered from 1, without the '\n' and without a
// trailing '\r'.
class LineCursor {
 public:
  explicit LineCursor(std::string_view text) : rest_(text) {}
  // False at the end of the text.
  bool Next(std::string_view* line);
  int line_number() const { return line_number_; }

 private:
  std::string_view rest_;
  int line_number_ = 0;
  bool done_ = false;
};

// Splits `line` at `separator` into fields[0..max_fields). Returns the number
// of fields the line has, which may exceed max_fields (then the extra ones
// are not stored).
std::size_t Split(std::string_view line, char separator, std::string_view* fields,
                  std::size_t max_fields);

}  // namespace parkslam::io::text

#endif  // PARKSLAM_IO_TEXT_UTIL_H_
