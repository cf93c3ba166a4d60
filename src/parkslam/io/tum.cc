#include "parkslam/io/tum.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>

#include "parkslam/common/plausible_ranges.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/io_error.h"
#include "parkslam/io/text_util.h"

namespace parkslam::io {
namespace {

constexpr int kColumns = 8;
constexpr std::array<const char*, kColumns> kColumnNames = {"t",  "x",  "y",  "z",
                                                            "qx", "qy", "qz", "qw"};
constexpr int kPositionDecimals = 6;
constexpr int kQuaternionDecimals = 10;
// Larger times overflow int64 nanoseconds.
constexpr std::uint64_t kMaxWholeSeconds = 9'000'000'000ULL;

// Exact text of a nanosecond time in seconds: "-12.000000500".
void AppendSeconds(std::string* out, TimeNs t_ns) {
  std::uint64_t magnitude =
      t_ns < 0 ? 0ULL - static_cast<std::uint64_t>(t_ns) : static_cast<std::uint64_t>(t_ns);
  if (t_ns < 0) out->push_back('-');
  const std::uint64_t ns_per_s = static_cast<std::uint64_t>(kNanosecondsPerSecond);
  out->append(std::to_string(magnitude / ns_per_s));
  std::string fraction = std::to_string(magnitude % ns_per_s);
  out->push_back('.');
  out->append(9 - fraction.size(), '0');
  out->append(fraction);
}

std::string SecondsText(TimeNs t_ns) {
  std::string text;
  AppendSeconds(&text, t_ns);
  return text;
}

bool IsDigit(char c) { return c >= '0' && c <= '9'; }

// Reads "[-+]digits[.digits]" exactly, rounding to the nanosecond; nullopt
// for other forms (exponents) and for times beyond the int64 range.
std::optional<TimeNs> ParsePlainSeconds(std::string_view text) {
  bool negative = false;
  if (!text.empty() && (text.front() == '-' || text.front() == '+')) {
    negative = text.front() == '-';
    text.remove_prefix(1);
  }
  std::uint64_t whole = 0, fraction = 0;
  std::size_t i = 0, whole_digits = 0;
  for (; i < text.size() && IsDigit(text[i]); ++i, ++whole_digits) {
    whole = whole * 10 + static_cast<std::uint64_t>(text[i] - '0');
    if (whole > kMaxWholeSeconds) return std::nullopt;
  }
  int fraction_digits = 0;
  bool round_up = false;
  if (i < text.size() && text[i] == '.') {
    for (++i; i < text.size() && IsDigit(text[i]); ++i) {
      if (fraction_digits < 9) {
        fraction = fraction * 10 + static_cast<std::uint64_t>(text[i] - '0');
        ++fraction_digits;
      } else if (fraction_digits == 9) {
        round_up = text[i] >= '5';
        ++fraction_digits;
      }
    }
  }
  if (i != text.size() || (whole_digits == 0 && fraction_digits == 0)) {
    return std::nullopt;
  }
  for (int d = std::min(fraction_digits, 9); d < 9; ++d) fraction *= 10;
  const std::uint64_t ns =
      whole * static_cast<std::uint64_t>(kNanosecondsPerSecond) + fraction + (round_up ? 1 : 0);
  const auto signed_ns = static_cast<TimeNs>(ns);
  return negative ? -signed_ns : signed_ns;
}

TimeNs ParseTime(std::string_view text, const std::string& source, int line) {
  if (const std::optional<TimeNs> t_ns = ParsePlainSeconds(text)) return *t_ns;
  const double t_s = text::ParseFiniteDouble(text, source, line, "t");
  if (std::abs(t_s) > static_cast<double>(kMaxWholeSeconds)) {
    ThrowIoError(source, line, "t", "out of range " + text::Quoted(text));
  }
  return FromSeconds(t_s);
}

// Splits at spaces and tabs; returns the number of fields found.
int SplitWhitespace(std::string_view line, std::array<std::string_view, kColumns>* fields) {
  int count = 0;
  std::size_t i = 0;
  while (true) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    if (i == line.size()) return count;
    const std::size_t begin = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (count < kColumns) (*fields)[count] = line.substr(begin, i - begin);
    ++count;
  }
}

TimedPose ParseLine(std::string_view line, const std::string& source, int line_number) {
  std::array<std::string_view, kColumns> fields;
  const int count = SplitWhitespace(line, &fields);
  if (count != kColumns) {
    ThrowIoError(source, line_number, "",
                 "expected 8 columns (t x y z qx qy qz qw), got " + std::to_string(count));
  }
  std::array<double, kColumns> values{};
  for (int c = 1; c < kColumns; ++c) {
    values[c] = text::ParseFiniteDouble(fields[c], source, line_number, kColumnNames[c]);
  }
  // The position in the map frame; z is dropped (the trajectory is planar)
  // and the quaternion normalized below.
  for (int c = 1; c <= 3; ++c) {
    if (std::abs(values[c]) > kMaxCoordinate_m) {
      ThrowIoError(source, line_number, kColumnNames[c],
                   text::BeyondPlausible(values[c], kMaxCoordinate_m, "m"));
    }
  }
  const double qx = values[4], qy = values[5], qz = values[6], qw = values[7];
  const double norm2 = qx * qx + qy * qy + qz * qz + qw * qw;
  if (!(norm2 > 1e-12) || !std::isfinite(norm2)) {
    ThrowIoError(source, line_number, "qx qy qz qw", "not a rotation (zero length)");
  }
  // Heading of the rotation (z-y-x Euler yaw); scale-invariant in q.
  const double yaw_rad =
      std::atan2(2.0 * (qw * qz + qx * qy), qw * qw + qx * qx - qy * qy - qz * qz);
  TimedPose pose;
  pose.t_ns = ParseTime(fields[0], source, line_number);
  pose.T_map_vehicle = SE2(values[1], values[2], yaw_rad);
  return pose;
}

void CheckWritable(const Trajectory& trajectory, const std::string& source) {
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    const SE2& T = trajectory[i].T_map_vehicle;
    const std::string where = "pose " + std::to_string(i);
    if (!std::isfinite(T.x()) || !std::isfinite(T.y()) || !std::isfinite(T.yaw())) {
      ThrowIoError(source, 0, where, "not a finite pose");
    }
    if (i > 0 && trajectory[i].t_ns <= trajectory[i - 1].t_ns) {
      ThrowIoError(source, 0, where,
                   "t not strictly increasing (" + SecondsText(trajectory[i].t_ns) + " s after " +
                       SecondsText(trajectory[i - 1].t_ns) + " s)");
    }
  }
}

}  // namespace

std::string FormatTum(const Trajectory& trajectory) {
  std::string out = "# t x y z qx qy qz qw\n";
  out.reserve(out.size() + trajectory.size() * 96);
  for (const TimedPose& pose : trajectory) {
    const SE2& T = pose.T_map_vehicle;
    const double half_yaw = 0.5 * T.yaw();
    AppendSeconds(&out, pose.t_ns);
    out.push_back(' ');
    text::AppendFixed(&out, T.x(), kPositionDecimals);
    out.push_back(' ');
    text::AppendFixed(&out, T.y(), kPositionDecimals);
    out += " 0 0 0 ";
    text::AppendFixed(&out, std::sin(half_yaw), kQuaternionDecimals);
    out.push_back(' ');
    text::AppendFixed(&out, std::cos(half_yaw), kQuaternionDecimals);
    out.push_back('\n');
  }
  return out;
}

Trajectory ParseTum(std::string_view content, const std::string& source_name) {
  Trajectory trajectory;
  text::LineCursor lines(content);
  std::string_view line;
  while (lines.Next(&line)) {
    line = text::Trim(line);
    if (line.empty() || line.front() == '#') continue;
    TimedPose pose = ParseLine(line, source_name, lines.line_number());
    if (!trajectory.empty() && pose.t_ns <= trajectory.back().t_ns) {
      ThrowIoError(source_name, lines.line_number(), "t",
                   "not strictly increasing (" + SecondsText(pose.t_ns) + " s after " +
                       SecondsText(trajectory.back().t_ns) + " s)");
    }
    trajectory.push_back(pose);
  }
  if (trajectory.empty()) ThrowIoError(source_name, 0, "", "no poses");
  return trajectory;
}

void WriteTum(const std::filesystem::path& path, const Trajectory& trajectory) {
  CheckWritable(trajectory, path.string());
  WriteFileAtomically(path, FormatTum(trajectory));
}

Trajectory ReadTum(const std::filesystem::path& path) {
  return ParseTum(ReadTextFile(path), path.string());
}

}  // namespace parkslam::io
