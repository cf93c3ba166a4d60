#include "parkslam/io/dataset.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <string_view>
#include <system_error>
#include <vector>

#include "parkslam/common/plausible_ranges.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/image_folder.h"
#include "parkslam/io/image_header.h"
#include "parkslam/io/io_error.h"
#include "parkslam/io/json_util.h"
#include "parkslam/io/map_json.h"
#include "parkslam/io/rig_yaml.h"
#include "parkslam/io/text_util.h"
#include "parkslam/io/tum.h"
#include "parkslam/io/yaml_util.h"

namespace parkslam::io {
namespace {

namespace fs = std::filesystem;
using json_util::Json;
using json_util::JsonPath;
using json_util::JsonReader;
using yaml_util::YamlReader;

constexpr char kWheelSpeedFile[] = "sensors/wheel_speed.csv";
constexpr char kSteeringFile[] = "sensors/steering.csv";
constexpr char kImuFile[] = "sensors/imu.csv";
constexpr char kSlotsFile[] = "observations/slots.jsonl";
constexpr char kTagsFile[] = "observations/tags.jsonl";
constexpr char kTrajectoryFile[] = "groundtruth/trajectory.tum";
constexpr char kMapFile[] = "groundtruth/map.json";
constexpr char kLabelsFile[] = "groundtruth/slot_labels.jsonl";

constexpr std::string_view kWheelSpeedHeader = "t_ns,speed_mps";
constexpr std::string_view kSteeringHeader = "t_ns,steering_wheel_rad";
constexpr std::string_view kImuHeader = "t_ns,yaw_rate_radps,heading_rad";
// heading_rad (value column 1) is empty for a gyro-only IMU.
constexpr unsigned kImuHeadingOptional = 1u << 1;

// What dataset.yaml announces besides the scenario.
struct Counts {
  std::int64_t wheel_speed = 0, steering = 0, imu = 0, slot_frames = 0, tag_frames = 0;
  std::int64_t trajectory_poses = 0, slot_label_frames = 0;
  bool map = false;
};

struct LabelFrame {
  TimeNs t_ns = 0;
  std::vector<int> slots;
};

// The streams of one drive start and end within this of each other
// (CheckDataset): cameras and sensors switched on a few seconds apart are
// normal, a minute is not one drive.
constexpr double kMaxStreamSkew_s = 60.0;

// Sensor streams (docs/dataset_format.md): time starts at 0 and a stream
// may pause for at most this long; a longer gap is a broken recording, not
// something to dead-reckon through (it would be hours of output).
constexpr TimeNs kMaxSensorGapNs = 10'000'000'000;

std::string Where(std::size_t index, TimeNs t_ns) {
  return " (entry " + std::to_string(index) + ", t_ns " + std::to_string(t_ns) + ")";
}

std::string NotIncreasing(TimeNs t_ns, TimeNs previous_t_ns) {
  return "not strictly increasing (" + std::to_string(t_ns) + " after " +
         std::to_string(previous_t_ns) + ")";
}

std::size_t CountLines(std::string_view content) {
  return static_cast<std::size_t>(std::count(content.begin(), content.end(), '\n')) + 1;
}

template <typename Stamped>
TimeNs Front(const std::vector<Stamped>& v) {
  return v.empty() ? std::numeric_limits<TimeNs>::max() : v.front().t_ns;
}
template <typename Stamped>
TimeNs Back(const std::vector<Stamped>& v) {
  return v.empty() ? std::numeric_limits<TimeNs>::min() : v.back().t_ns;
}

double DurationSeconds(const SensorLog& log) {
  const TimeNs first =
      std::min({Front(log.wheel_speeds), Front(log.steering_angles), Front(log.imu_samples),
                Front(log.slot_frames), Front(log.tag_frames)});
  const TimeNs last =
      std::max({Back(log.wheel_speeds), Back(log.steering_angles), Back(log.imu_samples),
                Back(log.slot_frames), Back(log.tag_frames)});
  // Division, not ToSeconds(): 300000000 ns reads as 0.3, not 0.30000000000000004.
  return last >= first ? static_cast<double>(last - first) / 1e9 : 0.0;
}

// ---------------------------------------------------------------------------
// CSV files: "t_ns,<value>,<value>..." with an exact header.

template <std::size_t kValues>
std::array<std::string_view, kValues + 1> ColumnNames(std::string_view header) {
  std::array<std::string_view, kValues + 1> names;
  text::Split(header, ',', names.data(), names.size());
  return names;
}

// A column that may be left empty (an IMU without a compass): NaN in the
// values stands for an empty field, both ways.
using OptionalColumns = unsigned;
constexpr OptionalColumns kNoOptionalColumns = 0;
constexpr bool IsOptionalColumn(OptionalColumns optional, std::size_t c) {
  return (optional >> c) & 1u;
}

template <std::size_t kValues, typename Sample, typename GetValues>
void WriteCsv(const fs::path& file, std::string_view header, const std::vector<Sample>& samples,
              GetValues get_values, OptionalColumns optional = kNoOptionalColumns) {
  const auto names = ColumnNames<kValues>(header);
  const std::string source = file.string();
  std::string out;
  out.reserve(header.size() + 1 + samples.size() * (21 + 25 * kValues));
  out.append(header);
  out.push_back('\n');
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const TimeNs t_ns = samples[i].t_ns;
    if (i > 0 && t_ns <= samples[i - 1].t_ns) {
      ThrowIoError(source, 0, "t_ns", NotIncreasing(t_ns, samples[i - 1].t_ns) + Where(i, t_ns));
    }
    const std::array<double, kValues> values = get_values(samples[i]);
    text::AppendInteger(&out, t_ns);
    for (std::size_t c = 0; c < kValues; ++c) {
      out.push_back(',');
      if (std::isnan(values[c]) && IsOptionalColumn(optional, c)) continue;
      if (!std::isfinite(values[c])) {
        ThrowIoError(source, 0, names[c + 1], "not a finite number" + Where(i, t_ns));
      }
      text::AppendDouble(&out, values[c]);
    }
    out.push_back('\n');
  }
  WriteFileAtomically(file, out);
}

// The plausible magnitude of a column's values (common/plausible_ranges.h):
// a value beyond is a broken recording, and would otherwise drive the
// filters to infinities far from its file.
struct Magnitude {
  double max_abs;
  const char* unit;
};

template <std::size_t kValues, typename Sample, typename MakeSample>
std::vector<Sample> ReadCsv(const fs::path& file, std::string_view header,
                            const std::array<Magnitude, kValues>& limits, MakeSample make_sample,
                            OptionalColumns optional = kNoOptionalColumns) {
  const auto names = ColumnNames<kValues>(header);
  const std::string source = file.string();
  const std::string content = ReadTextFile(file);
  text::LineCursor lines(content);
  std::string_view line;
  if (!lines.Next(&line) || line != header) {
    ThrowIoError(source, 1, "",
                 "expected the header " + text::Quoted(header) + ", got " + text::Quoted(line));
  }
  std::vector<Sample> samples;
  samples.reserve(CountLines(content));
  std::array<std::string_view, kValues + 1> fields;
  std::array<double, kValues> values;
  while (lines.Next(&line)) {
    const int n = lines.line_number();
    if (line.empty()) ThrowIoError(source, n, "", "empty line");
    const std::size_t count = text::Split(line, ',', fields.data(), fields.size());
    if (count != fields.size()) {
      ThrowIoError(
          source, n, "",
          "expected " + std::to_string(fields.size()) + " fields, got " + std::to_string(count));
    }
    const std::optional<std::int64_t> t_ns = text::ParseInt64(fields[0]);
    if (!t_ns) ThrowIoError(source, n, "t_ns", "not an integer " + text::Quoted(fields[0]));
    if (!samples.empty() && *t_ns <= samples.back().t_ns) {
      ThrowIoError(source, n, "t_ns", NotIncreasing(*t_ns, samples.back().t_ns));
    }
    if (*t_ns < 0) ThrowIoError(source, n, "t_ns", "below zero (time starts at 0)");
    if (!samples.empty() && *t_ns - samples.back().t_ns > kMaxSensorGapNs) {
      ThrowIoError(source, n, "t_ns",
                   "a gap of " + std::to_string((*t_ns - samples.back().t_ns) / 1'000'000) +
                       " ms after the previous sample (at most 10 s; split the recording there)");
    }
    for (std::size_t c = 0; c < kValues; ++c) {
      if (fields[c + 1].empty() && IsOptionalColumn(optional, c)) {
        values[c] = std::numeric_limits<double>::quiet_NaN();
        continue;
      }
      values[c] = text::ParseFiniteDouble(fields[c + 1], source, n, names[c + 1]);
      if (std::abs(values[c]) > limits[c].max_abs) {
        ThrowIoError(source, n, names[c + 1],
                     text::BeyondPlausible(values[c], limits[c].max_abs, limits[c].unit));
      }
    }
    samples.push_back(make_sample(*t_ns, values));
  }
  return samples;
}

// ---------------------------------------------------------------------------
// JSON-lines files: one frame a line.

// Appends numbers of one frame, failing on values that would not read back.
class FrameWriter {
 public:
  FrameWriter(std::string source, const char* list_key, std::string* out)
      : source_(std::move(source)), list_key_(list_key), out_(out) {}

  void StartFrame(std::size_t index, TimeNs t_ns, std::optional<TimeNs> previous_t_ns) {
    frame_ = index;
    t_ns_ = t_ns;
    item_ = -1;
    if (previous_t_ns && t_ns <= *previous_t_ns) Fail("t_ns", NotIncreasing(t_ns, *previous_t_ns));
    out_->append("{\"t_ns\":");
    text::AppendInteger(out_, t_ns);
  }
  void StartItem(std::size_t index) { item_ = static_cast<std::ptrdiff_t>(index); }
  void Number(double value, const char* field) {
    if (!std::isfinite(value)) Fail(field, "not a finite number");
    text::AppendDouble(out_, value);
  }
  void Integer(std::int64_t value) { text::AppendInteger(out_, value); }
  void Bool(bool value) { out_->append(value ? "true" : "false"); }
  void Raw(std::string_view text) { out_->append(text); }

  [[noreturn]] void Fail(const char* field, const std::string& what) const {
    std::string path;
    if (item_ >= 0) path = std::string(list_key_) + "[" + std::to_string(item_) + "].";
    path += field;
    ThrowIoError(source_, 0, path, what + Where(frame_, t_ns_));
  }

 private:
  std::string source_;
  const char* list_key_;
  std::string* out_;
  std::size_t frame_ = 0;
  TimeNs t_ns_ = 0;
  std::ptrdiff_t item_ = -1;
};

void AppendPoint(FrameWriter& w, const Eigen::Vector2d& p, const char* field) {
  w.Raw("[");
  w.Number(p.x(), field);
  w.Raw(",");
  w.Number(p.y(), field);
  w.Raw("]");
}

void AppendSlotId(FrameWriter& w, const SlotIdReading& id) {
  w.Raw("[");
  for (std::size_t d = 0; d < id.digits.size(); ++d) {
    w.Raw(d > 0 ? ",[" : "[");
    const std::vector<DigitHypothesis>& hypotheses = id.digits[d].hypotheses;
    for (std::size_t h = 0; h < hypotheses.size(); ++h) {
      const char digit = hypotheses[h].digit;
      if (digit < 0x20 || digit > 0x7e || digit == '"' || digit == '\\') {
        w.Fail("id", "digit is not a plain printable character");
      }
      w.Raw(h > 0 ? ",[\"" : "[\"");
      w.Raw(std::string_view(&digit, 1));
      w.Raw("\",");
      w.Number(hypotheses[h].probability, "id");
      w.Raw("]");
    }
    w.Raw("]");
  }
  w.Raw("]");
}

void AppendSlot(FrameWriter& w, const SlotObservation& slot) {
  w.Raw("{\"corners\":[");
  for (int c = 0; c < kSlotCorners; ++c) {
    if (c > 0) w.Raw(",");
    AppendPoint(w, slot.corners_vehicle[static_cast<std::size_t>(c)], "corners");
  }
  w.Raw("],\"observed\":[");
  for (int c = 0; c < kSlotCorners; ++c) {
    if (c > 0) w.Raw(",");
    w.Bool(slot.corner_observed[static_cast<std::size_t>(c)]);
  }
  w.Raw("],\"sigma_m\":");
  w.Number(slot.corner_sigma_m, "sigma_m");
  w.Raw(",\"confidence\":");
  w.Number(slot.detection_confidence, "confidence");
  w.Raw(",\"id\":");
  AppendSlotId(w, slot.id);
  w.Raw("}");
}

void AppendTag(FrameWriter& w, const TagObservation& tag) {
  w.Raw("{\"id\":");
  w.Integer(tag.tag_id);
  w.Raw(",\"x_m\":");
  w.Number(tag.p_vehicle.x(), "x_m");
  w.Raw(",\"y_m\":");
  w.Number(tag.p_vehicle.y(), "y_m");
  w.Raw(",\"range_m\":");
  w.Number(tag.range_m, "range_m");
  w.Raw(",\"bearing_rad\":");
  w.Number(tag.bearing_rad, "bearing_rad");
  w.Raw(",\"yaw_rad\":");
  w.Number(tag.yaw_vehicle_rad, "yaw_rad");
  w.Raw(",\"cov\":[");
  w.Number(tag.covariance_vehicle(0, 0), "cov");
  w.Raw(",");
  w.Number(tag.covariance_vehicle(0, 1), "cov");
  w.Raw(",");
  w.Number(tag.covariance_vehicle(1, 1), "cov");
  w.Raw("],\"yaw_sigma_rad\":");
  w.Number(tag.yaw_sigma_rad, "yaw_sigma_rad");
  w.Raw("}");
}

// Writes one line per frame; AppendItem(writer, item) writes one element of
// the frame's `items` list.
template <typename Frame, typename Items, typename AppendItem>
void WriteJsonl(const fs::path& file, const char* list_key, const std::vector<Frame>& frames,
                Items items, AppendItem append_item) {
  std::string out;
  out.reserve(frames.size() * 64);
  FrameWriter w(file.string(), list_key, &out);
  for (std::size_t f = 0; f < frames.size(); ++f) {
    w.StartFrame(f, frames[f].t_ns,
                 f > 0 ? std::optional<TimeNs>(frames[f - 1].t_ns) : std::nullopt);
    w.Raw(",\"");
    w.Raw(list_key);
    w.Raw("\":[");
    const auto& list = items(frames[f]);
    for (std::size_t i = 0; i < list.size(); ++i) {
      if (i > 0) w.Raw(",");
      w.StartItem(i);
      append_item(w, list[i]);
    }
    w.Raw("]}\n");
  }
  WriteFileAtomically(file, out);
}

template <typename Frame, typename ParseFrame>
std::vector<Frame> ReadJsonl(const fs::path& file, ParseFrame parse_frame) {
  const std::string source = file.string();
  const std::string content = ReadTextFile(file);
  std::vector<Frame> frames;
  frames.reserve(CountLines(content));
  text::LineCursor lines(content);
  std::string_view line;
  while (lines.Next(&line)) {
    const int n = lines.line_number();
    if (line.empty()) ThrowIoError(source, n, "", "empty line");
    const Json json = json_util::ParseJson(line, source, n);
    const JsonReader reader(source, n);
    Frame frame = parse_frame(json, reader);
    if (!frames.empty() && frame.t_ns <= frames.back().t_ns) {
      ThrowIoError(source, n, "t_ns", NotIncreasing(frame.t_ns, frames.back().t_ns));
    }
    frames.push_back(std::move(frame));
  }
  return frames;
}

double Probability(const Json& j, const JsonReader& r, const JsonPath& path) {
  const double p = r.Number(j, path);
  if (p < 0.0 || p > 1.0) r.Fail(path, "must be in [0, 1]");
  return p;
}

SlotIdReading ParseSlotId(const Json& j, const JsonReader& r, const JsonPath& path) {
  r.ExpectArray(j, path);
  // Painted IDs have a few digits (the lots here 2-3, real ones up to 4).
  constexpr std::size_t kMaxIdDigits = 8;
  if (j.size() > kMaxIdDigits) {
    r.Fail(path, std::to_string(j.size()) + " digits; a painted ID has at most " +
                     std::to_string(kMaxIdDigits));
  }
  SlotIdReading id;
  id.digits.resize(j.size());
  for (std::size_t d = 0; d < j.size(); ++d) {
    const JsonPath digit_path = path.Index(d);
    const Json& digit = j[d];
    r.ExpectArray(digit, digit_path);
    for (std::size_t h = 0; h < digit.size(); ++h) {
      const JsonPath hypothesis_path = digit_path.Index(h);
      const JsonPath text_path = hypothesis_path.Index(0);
      const JsonPath probability_path = hypothesis_path.Index(1);
      const Json& hypothesis = digit[h];
      r.ExpectArray(hypothesis, hypothesis_path, 2, "entries [digit, probability]");
      const std::string& text = r.String(hypothesis[0], text_path);
      if (text.size() != 1 || text[0] < '0' || text[0] > '9') {
        r.Fail(text_path, "expected one digit 0-9, got '" + text + "'");
      }
      id.digits[d].hypotheses.push_back({text[0], Probability(hypothesis[1], r, probability_path)});
    }
    double total = 0.0;
    for (const auto& h : id.digits[d].hypotheses) total += h.probability;
    if (total > 1.0 + 1e-6) {
      r.Fail(digit_path, "its probabilities add up to " + std::to_string(total) + ", more than 1");
    }
  }
  return id;
}

SlotObservation ParseSlot(const Json& j, const JsonReader& r, const JsonPath& path) {
  r.ExpectObject(j, path, {"corners", "observed", "sigma_m", "confidence", "id"});
  SlotObservation slot;
  const JsonPath corners = path.Key("corners");
  const JsonPath observed = path.Key("observed");
  const Json& corners_json = j["corners"];
  const Json& observed_json = j["observed"];
  r.ExpectArray(corners_json, corners, kSlotCorners, "points");
  r.ExpectArray(observed_json, observed, kSlotCorners, "booleans");
  for (std::size_t c = 0; c < static_cast<std::size_t>(kSlotCorners); ++c) {
    const JsonPath corner = corners.Index(c);
    const JsonPath flag = observed.Index(c);
    slot.corners_vehicle[c] = r.Point(corners_json[c], corner, kMaxObservationRange_m, "m");
    slot.corner_observed[c] = r.Bool(observed_json[c], flag);
  }
  json_util::CheckSlotArea(slot.corners_vehicle, r, corners);
  slot.corner_sigma_m =
      r.NumberIn(j["sigma_m"], path.Key("sigma_m"), 0.0, kMaxPositionSigma_m, "m");
  slot.detection_confidence = Probability(j["confidence"], r, path.Key("confidence"));
  slot.id = ParseSlotId(j["id"], r, path.Key("id"));
  return slot;
}

// One JSON line of a frame file: {"t_ns": ..., "<list_key>": [item, ...]},
// each item read by parse_item(json, reader, path).
template <typename Frame, typename ParseItem>
Frame ParseFrame(const Json& j, const JsonReader& r, const char* list_key, auto Frame::*items,
                 ParseItem parse_item) {
  const JsonPath root;
  r.ExpectObject(j, root, {"t_ns", list_key});
  Frame frame;
  frame.t_ns = r.Integer(j["t_ns"], root.Key("t_ns"));
  const JsonPath list = root.Key(list_key);
  const Json& list_json = j[list_key];
  r.ExpectArray(list_json, list);
  (frame.*items).reserve(list_json.size());
  for (std::size_t i = 0; i < list_json.size(); ++i) {
    (frame.*items).push_back(parse_item(list_json[i], r, list.Index(i)));
  }
  return frame;
}

SlotObservationFrame ParseSlotFrame(const Json& j, const JsonReader& r) {
  return ParseFrame<SlotObservationFrame>(j, r, "slots", &SlotObservationFrame::slots, ParseSlot);
}

TagObservation ParseTag(const Json& j, const JsonReader& r, const JsonPath& path) {
  r.ExpectObject(j, path,
                 {"id", "x_m", "y_m", "range_m", "bearing_rad", "yaw_rad", "cov", "yaw_sigma_rad"});
  TagObservation tag;
  tag.tag_id = r.Int(j["id"], path.Key("id"));
  if (tag.tag_id < 0 || tag.tag_id >= kTagIdCount) {
    r.Fail(path.Key("id"), "must be a tag36h11 ID in [0, " + std::to_string(kTagIdCount - 1) +
                               "], got " + std::to_string(tag.tag_id));
  }
  tag.p_vehicle =
      Eigen::Vector2d(r.BoundedNumber(j["x_m"], path.Key("x_m"), kMaxObservationRange_m, "m"),
                      r.BoundedNumber(j["y_m"], path.Key("y_m"), kMaxObservationRange_m, "m"));
  // In magnitude only: a simulated range carries noise, and the tag's
  // position is x_m, y_m.
  tag.range_m = r.BoundedNumber(j["range_m"], path.Key("range_m"), kMaxObservationRange_m, "m");
  tag.bearing_rad =
      r.BoundedNumber(j["bearing_rad"], path.Key("bearing_rad"), kMaxAngle_rad, "rad");
  tag.yaw_vehicle_rad = r.BoundedNumber(j["yaw_rad"], path.Key("yaw_rad"), kMaxAngle_rad, "rad");
  const JsonPath cov = path.Key("cov");
  const Json& cov_json = j["cov"];
  r.ExpectArray(cov_json, cov, 3, "numbers [xx, xy, yy]");
  const JsonPath xx_path = cov.Index(0);
  const JsonPath xy_path = cov.Index(1);
  const JsonPath yy_path = cov.Index(2);
  constexpr double kMaxVariance_m2 = kMaxPositionSigma_m * kMaxPositionSigma_m;
  const double xx = r.NumberIn(cov_json[0], xx_path, 0.0, kMaxVariance_m2, "m^2");
  const double xy = r.BoundedNumber(cov_json[1], xy_path, kMaxVariance_m2, "m^2");
  const double yy = r.NumberIn(cov_json[2], yy_path, 0.0, kMaxVariance_m2, "m^2");
  // Positive semi-definite, as every covariance: a noise-free simulation
  // writes zero, and a single noisy direction a singular one, whose xx yy
  // may come out a rounding below xy^2.
  if (xy * xy > xx * yy * (1.0 + 1e-9)) {
    r.Fail(cov, "not a covariance: xy^2 exceeds xx yy");
  }
  tag.covariance_vehicle << xx, xy, xy, yy;
  tag.yaw_sigma_rad =
      r.NumberIn(j["yaw_sigma_rad"], path.Key("yaw_sigma_rad"), 0.0, kMaxAngleSigma_rad, "rad");
  return tag;
}

TagObservationFrame ParseTagFrame(const Json& j, const JsonReader& r) {
  return ParseFrame<TagObservationFrame>(j, r, "tags", &TagObservationFrame::tags, ParseTag);
}

LabelFrame ParseLabelFrame(const Json& j, const JsonReader& r) {
  return ParseFrame<LabelFrame>(
      j, r, "slots", &LabelFrame::slots,
      [](const Json& item, const JsonReader& reader, const JsonPath& path) {
        const int label = reader.Int(item, path);
        if (label < -1) reader.Fail(path, "must be a slot index or -1");
        return label;
      });
}

// ---------------------------------------------------------------------------
// Ground-truth labels.

// Labels must be absent or give one label per slot observation.
void CheckLabelsMatch(const Dataset& dataset, const std::string& source) {
  const SensorLog& log = dataset.log;
  if (dataset.slot_labels.empty()) return;
  if (dataset.slot_labels.size() != log.slot_frames.size()) {
    ThrowIoError(source, 0, "",
                 std::to_string(dataset.slot_labels.size()) + " label frames for " +
                     std::to_string(log.slot_frames.size()) + " slot frames");
  }
  const std::size_t map_slots = dataset.groundtruth_map ? dataset.groundtruth_map->slots.size()
                                                        : std::numeric_limits<std::size_t>::max();
  for (std::size_t f = 0; f < log.slot_frames.size(); ++f) {
    const std::vector<int>& labels = dataset.slot_labels[f];
    if (labels.size() != log.slot_frames[f].slots.size()) {
      ThrowIoError(source, 0, "slots",
                   std::to_string(labels.size()) + " labels for " +
                       std::to_string(log.slot_frames[f].slots.size()) + " observations" +
                       Where(f, log.slot_frames[f].t_ns));
    }
    for (const int label : labels) {
      if (label < -1 || (label >= 0 && static_cast<std::size_t>(label) >= map_slots)) {
        ThrowIoError(source, 0, "slots",
                     "label " + std::to_string(label) + " is no slot of the map" +
                         Where(f, log.slot_frames[f].t_ns));
      }
    }
  }
}

void WriteLabels(const fs::path& file, const Dataset& dataset) {
  std::string out;
  out.reserve(dataset.slot_labels.size() * 40);
  for (std::size_t f = 0; f < dataset.slot_labels.size(); ++f) {
    out.append("{\"t_ns\":");
    text::AppendInteger(&out, dataset.log.slot_frames[f].t_ns);
    out.append(",\"slots\":[");
    const std::vector<int>& labels = dataset.slot_labels[f];
    for (std::size_t i = 0; i < labels.size(); ++i) {
      if (i > 0) out.push_back(',');
      text::AppendInteger(&out, labels[i]);
    }
    out.append("]}\n");
  }
  WriteFileAtomically(file, out);
}

// Label frame i must carry the time and the observation count of slot frame i.
sim::SlotObservationLabels MatchLabels(const std::vector<LabelFrame>& frames,
                                       const Dataset& dataset, const std::string& source) {
  const std::vector<SlotObservationFrame>& slot_frames = dataset.log.slot_frames;
  const std::size_t map_slots = dataset.groundtruth_map ? dataset.groundtruth_map->slots.size()
                                                        : std::numeric_limits<std::size_t>::max();
  sim::SlotObservationLabels labels;
  labels.reserve(frames.size());
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const int line = static_cast<int>(f) + 1;
    if (f >= slot_frames.size()) {
      ThrowIoError(
          source, line, "",
          "more label frames than slot frames (" + std::to_string(slot_frames.size()) + ")");
    }
    if (frames[f].t_ns != slot_frames[f].t_ns) {
      ThrowIoError(source, line, "t_ns",
                   std::to_string(frames[f].t_ns) + " does not match slot frame " +
                       std::to_string(f) + " at " + std::to_string(slot_frames[f].t_ns));
    }
    if (frames[f].slots.size() != slot_frames[f].slots.size()) {
      ThrowIoError(source, line, "slots",
                   std::to_string(frames[f].slots.size()) + " labels for " +
                       std::to_string(slot_frames[f].slots.size()) + " observations");
    }
    for (std::size_t i = 0; i < frames[f].slots.size(); ++i) {
      const int label = frames[f].slots[i];
      if (label >= 0 && static_cast<std::size_t>(label) >= map_slots) {
        ThrowIoError(source, line, "slots[" + std::to_string(i) + "]",
                     "label " + std::to_string(label) + " out of range (" + kMapFile + " has " +
                         std::to_string(map_slots) + " slots)");
      }
    }
    labels.push_back(frames[f].slots);
  }
  if (labels.size() != slot_frames.size()) {
    ThrowIoError(source, 0, "",
                 std::to_string(labels.size()) + " label frames for " +
                     std::to_string(slot_frames.size()) + " slot frames");
  }
  return labels;
}

// ---------------------------------------------------------------------------
// dataset.yaml

void AppendKey(std::string* out, int indent, const char* key) {
  out->append(static_cast<std::size_t>(indent), ' ');
  out->append(key);
  out->append(": ");
}

void AppendCount(std::string* out, const char* key, std::size_t count) {
  AppendKey(out, 2, key);
  out->append(std::to_string(count));
  out->push_back('\n');
}

std::string ManifestYaml(const Dataset& d) {
  std::string out =
      "# parkslam dataset (io/dataset.h). Written after all other files: its\n"
      "# presence marks a complete dataset.\n";
  AppendKey(&out, 0, "format");
  yaml_util::AppendYamlString(&out, kDatasetFormatName);
  out += "\nversion: " + std::to_string(kDatasetFormatVersion) + "\n";
  AppendKey(&out, 0, "name");
  yaml_util::AppendYamlString(&out, d.name);
  out += "\nseed: " + std::to_string(d.seed) + "\n";
  AppendKey(&out, 0, "created_by");
  yaml_util::AppendYamlString(&out, d.created_by);
  out += "\n";
  AppendKey(&out, 0, "duration_s");
  yaml_util::AppendYamlDouble(&out, DurationSeconds(d.log));
  out += "\ncounts:\n";
  AppendCount(&out, "wheel_speed", d.log.wheel_speeds.size());
  AppendCount(&out, "steering", d.log.steering_angles.size());
  AppendCount(&out, "imu", d.log.imu_samples.size());
  AppendCount(&out, "slot_frames", d.log.slot_frames.size());
  AppendCount(&out, "tag_frames", d.log.tag_frames.size());
  out += "groundtruth:\n";
  AppendCount(&out, "trajectory_poses", d.groundtruth_trajectory.size());
  AppendKey(&out, 2, "map");
  out += d.groundtruth_map ? "true\n" : "false\n";
  AppendCount(&out, "slot_label_frames", d.slot_labels.size());
  out += "vehicle:\n";
  yaml_util::AppendVehicleYaml(d.vehicle, 2, &out);
  out += "sensors:\n  odometry:\n";
  yaml_util::AppendOdometrySpecYaml(d.odometry_spec, 4, &out);
  if (d.scenario) {
    out += "scenario:\n";
    yaml_util::AppendScenarioYaml(*d.scenario, 2, &out);
  }
  return out;
}

std::int64_t Count(const YamlReader& r, const YAML::Node& node, const std::string& path) {
  const std::int64_t count = r.Int64(node, path);
  if (count < 0) r.Fail(node, path, "must not be negative");
  return count;
}

void CheckFormat(const YamlReader& r, const YAML::Node& root) {
  r.ExpectMap(root, "");
  const YAML::Node format = root["format"];
  if (!format) r.Fail(root, "format", "missing key (not a parkslam dataset)");
  const std::string name = r.String(format, "format");
  if (name != kDatasetFormatName) {
    r.Fail(format, "format",
           "expected '" + std::string(kDatasetFormatName) + "', got '" + name + "'");
  }
  const YAML::Node version = root["version"];
  if (!version) r.Fail(root, "version", "missing key");
  const std::int64_t number = r.Int64(version, "version");
  if (number != kDatasetFormatVersion && number != 1) {
    r.Fail(version, "version",
           "unsupported version " + std::to_string(number) + " (this build reads " +
               std::to_string(kDatasetFormatVersion) + ")");
  }
}

// The vehicle, the odometry specification and the optional scenario. In
// version 1 the first two live only inside the scenario.
void ReadCarAndScenario(const YAML::Node& root, const YamlReader& r, bool version_1,
                        Dataset* dataset) {
  std::string error;
  if (root["scenario"]) {
    sim::ScenarioConfig scenario = sim::DefaultScenario();
    yaml_util::ReadScenarioNode(r, root["scenario"], "scenario", &scenario);
    if (!scenario.IsValid(&error)) r.Fail(root["scenario"], "", "scenario." + error);
    dataset->scenario = scenario;
  }
  if (version_1) {
    dataset->vehicle = dataset->scenario->vehicle;
    dataset->odometry_spec = dataset->scenario->sensors.odometry;
    return;
  }
  const YAML::Node vehicle = root["vehicle"];
  if (!vehicle) r.Fail(root, "vehicle", "missing key (the car's wheelbase, steering ratio, size)");
  yaml_util::ReadVehicleNode(r, vehicle, "vehicle", &dataset->vehicle);
  if (!dataset->vehicle.IsValid(&error)) r.Fail(vehicle, "", error);
  const YAML::Node sensors = root["sensors"];
  if (!sensors) r.Fail(root, "sensors", "missing key (the odometry sensors' rates and noise)");
  r.ExpectKeys(sensors, "sensors", {"odometry"});
  yaml_util::ReadOdometrySpecNode(r, sensors["odometry"], "sensors.odometry",
                                  &dataset->odometry_spec);
  if (!dataset->odometry_spec.IsValid(&error)) r.Fail(sensors["odometry"], "", error);
  // A simulated dataset's scenario must describe the same car.
  if (dataset->scenario) {
    std::string in_scenario, top_level;
    yaml_util::AppendVehicleYaml(dataset->scenario->vehicle, 0, &in_scenario);
    yaml_util::AppendVehicleYaml(dataset->vehicle, 0, &top_level);
    if (in_scenario != top_level) {
      r.Fail(root["scenario"]["vehicle"], "scenario.vehicle", "differs from the vehicle section");
    }
    in_scenario.clear();
    top_level.clear();
    yaml_util::AppendOdometrySpecYaml(dataset->scenario->sensors.odometry, 0, &in_scenario);
    yaml_util::AppendOdometrySpecYaml(dataset->odometry_spec, 0, &top_level);
    if (in_scenario != top_level) {
      r.Fail(root["scenario"]["sensors"], "scenario.sensors.odometry",
             "differs from the sensors.odometry section");
    }
  }
}

// Reads dataset.yaml into the dataset's header fields and returns the counts.
Counts ReadManifest(const YAML::Node& root, const YamlReader& r, Dataset* dataset) {
  CheckFormat(r, root);
  const bool version_1 = r.Int64(root["version"], "version") == 1;
  if (version_1) {
    r.ExpectKeys(root, "",
                 {"format", "version", "name", "seed", "created_by", "duration_s", "counts",
                  "groundtruth", "scenario"});
  } else {
    r.CheckKeys(root, "",
                {"format", "version", "name", "seed", "created_by", "duration_s", "counts",
                 "groundtruth", "vehicle", "sensors", "scenario"});
  }
  dataset->name = r.String(root["name"], "name");
  dataset->seed = r.Uint64(root["seed"], "seed");
  dataset->created_by = r.String(root["created_by"], "created_by");
  if (r.Double(root["duration_s"], "duration_s") < 0.0) {
    r.Fail(root["duration_s"], "duration_s", "must not be negative");
  }
  Counts counts;
  const YAML::Node c = root["counts"];
  r.ExpectKeys(c, "counts", {"wheel_speed", "steering", "imu", "slot_frames", "tag_frames"});
  counts.wheel_speed = Count(r, c["wheel_speed"], "counts.wheel_speed");
  counts.steering = Count(r, c["steering"], "counts.steering");
  counts.imu = Count(r, c["imu"], "counts.imu");
  counts.slot_frames = Count(r, c["slot_frames"], "counts.slot_frames");
  counts.tag_frames = Count(r, c["tag_frames"], "counts.tag_frames");
  const YAML::Node g = root["groundtruth"];
  r.ExpectKeys(g, "groundtruth", {"trajectory_poses", "map", "slot_label_frames"});
  counts.trajectory_poses = Count(r, g["trajectory_poses"], "groundtruth.trajectory_poses");
  counts.map = r.Bool(g["map"], "groundtruth.map");
  counts.slot_label_frames = Count(r, g["slot_label_frames"], "groundtruth.slot_label_frames");
  ReadCarAndScenario(root, r, version_1, dataset);
  return counts;
}

// The number a file holds must be the one dataset.yaml announces.
void CheckCount(const YamlReader& r, const YAML::Node& node, const std::string& path,
                std::int64_t announced, std::size_t found, const char* file) {
  if (static_cast<std::size_t>(announced) == found) return;
  r.Fail(
      node, path,
      "announces " + std::to_string(announced) + ", but " + file + " has " + std::to_string(found));
}

void RemoveStale(const fs::path& file) {
  std::error_code error;
  fs::remove(file, error);
  if (error) ThrowIoError(file.string(), 0, "", "cannot remove: " + error.message());
}

}  // namespace

void SetScenario(const sim::ScenarioConfig& scenario, Dataset* dataset) {
  dataset->scenario = scenario;
  dataset->vehicle = scenario.vehicle;
  dataset->odometry_spec = scenario.sensors.odometry;
}

void WriteDataset(const fs::path& dir, const Dataset& dataset) {
  CheckLabelsMatch(dataset, (dir / kLabelsFile).string());
  RemoveStale(dir / kDatasetManifestFile);
  const SensorLog& log = dataset.log;
  WriteCsv<1>(dir / kWheelSpeedFile, kWheelSpeedHeader, log.wheel_speeds,
              [](const WheelSpeed& s) { return std::array<double, 1>{s.speed_mps}; });
  WriteCsv<1>(dir / kSteeringFile, kSteeringHeader, log.steering_angles,
              [](const SteeringAngle& s) { return std::array<double, 1>{s.steering_wheel_rad}; });
  WriteCsv<2>(
      dir / kImuFile, kImuHeader, log.imu_samples,
      [](const ImuSample& s) {
        return std::array<double, 2>{
            s.yaw_rate_radps, s.heading_rad.value_or(std::numeric_limits<double>::quiet_NaN())};
      },
      kImuHeadingOptional);
  WriteJsonl(
      dir / kSlotsFile, "slots", log.slot_frames,
      [](const SlotObservationFrame& f) -> const auto& { return f.slots; }, AppendSlot);
  WriteJsonl(
      dir / kTagsFile, "tags", log.tag_frames,
      [](const TagObservationFrame& f) -> const auto& { return f.tags; }, AppendTag);

  if (dataset.groundtruth_trajectory.empty()) {
    RemoveStale(dir / kTrajectoryFile);
  } else {
    WriteTum(dir / kTrajectoryFile, dataset.groundtruth_trajectory);
  }
  if (dataset.groundtruth_map) {
    WriteMap(dir / kMapFile, *dataset.groundtruth_map);
  } else {
    RemoveStale(dir / kMapFile);
  }
  if (dataset.slot_labels.empty()) {
    RemoveStale(dir / kLabelsFile);
  } else {
    WriteLabels(dir / kLabelsFile, dataset);
  }
  WriteFileAtomically(dir / kDatasetManifestFile, ManifestYaml(dataset));
}

namespace {

// Each file of a dataset, read and checked as ReadDataset and CheckDataset
// both need it.
YAML::Node LoadManifest(const fs::path& dir) {
  const fs::path manifest = dir / kDatasetManifestFile;
  std::error_code error;
  if (!fs::is_regular_file(manifest, error)) {
    ThrowIoError(manifest.string(), 0, "",
                 "missing: not a dataset folder, or a dataset not completely written");
  }
  return yaml_util::LoadYaml(ReadTextFile(manifest, kMaxYamlBytes), manifest.string());
}

std::vector<WheelSpeed> ReadWheelSpeeds(const fs::path& dir) {
  return ReadCsv<1, WheelSpeed>(dir / kWheelSpeedFile, kWheelSpeedHeader,
                                {{{kMaxWheelSpeed_mps, "m/s"}}},
                                [](TimeNs t, const std::array<double, 1>& v) {
                                  return WheelSpeed{t, v[0]};
                                });
}

std::vector<SteeringAngle> ReadSteeringAngles(const fs::path& dir) {
  return ReadCsv<1, SteeringAngle>(dir / kSteeringFile, kSteeringHeader,
                                   {{{kMaxSteeringWheelAngle_rad, "rad"}}},
                                   [](TimeNs t, const std::array<double, 1>& v) {
                                     return SteeringAngle{t, v[0]};
                                   });
}

std::vector<ImuSample> ReadImuSamples(const fs::path& dir) {
  return ReadCsv<2, ImuSample>(
      dir / kImuFile, kImuHeader, {{{kMaxYawRate_radps, "rad/s"}, {kMaxAngle_rad, "rad"}}},
      [](TimeNs t, const std::array<double, 2>& v) {
        return ImuSample{t, v[0], std::isnan(v[1]) ? std::nullopt : std::optional<double>(v[1])};
      },
      kImuHeadingOptional);
}

std::vector<SlotObservationFrame> ReadSlotFrames(const fs::path& dir) {
  return ReadJsonl<SlotObservationFrame>(dir / kSlotsFile, ParseSlotFrame);
}

std::vector<TagObservationFrame> ReadTagFrames(const fs::path& dir) {
  return ReadJsonl<TagObservationFrame>(dir / kTagsFile, ParseTagFrame);
}

}  // namespace

namespace {
StreamSummary Summarize(const std::string& name, std::vector<TimeNs> t_ns);
template <typename Samples>
std::vector<TimeNs> Times(const Samples& samples);
std::vector<std::string> StreamsApart(const fs::path& dir,
                                      const std::vector<StreamSummary>& streams);
}  // namespace

Dataset ReadDataset(const fs::path& dir) {
  const YAML::Node root = LoadManifest(dir);
  const std::string source = (dir / kDatasetManifestFile).string();
  const YamlReader r(source, true);
  Dataset dataset;
  const Counts counts = ReadManifest(root, r, &dataset);

  SensorLog& log = dataset.log;
  log.wheel_speeds = ReadWheelSpeeds(dir);
  log.steering_angles = ReadSteeringAngles(dir);
  log.imu_samples = ReadImuSamples(dir);
  log.slot_frames = ReadSlotFrames(dir);
  log.tag_frames = ReadTagFrames(dir);
  // As check-dataset: a stream that starts or ends far from the others (a
  // clock jumped by years) would have the dead reckoning step across the
  // gap, for ever.
  const std::vector<std::string> apart =
      StreamsApart(dir, {Summarize(kWheelSpeedFile, Times(log.wheel_speeds)),
                         Summarize(kSteeringFile, Times(log.steering_angles)),
                         Summarize(kImuFile, Times(log.imu_samples)),
                         Summarize(kSlotsFile, Times(log.slot_frames)),
                         Summarize(kTagsFile, Times(log.tag_frames))});
  if (!apart.empty()) throw std::runtime_error(apart.front());

  const YAML::Node c = root["counts"];
  CheckCount(r, c["wheel_speed"], "counts.wheel_speed", counts.wheel_speed, log.wheel_speeds.size(),
             kWheelSpeedFile);
  CheckCount(r, c["steering"], "counts.steering", counts.steering, log.steering_angles.size(),
             kSteeringFile);
  CheckCount(r, c["imu"], "counts.imu", counts.imu, log.imu_samples.size(), kImuFile);
  CheckCount(r, c["slot_frames"], "counts.slot_frames", counts.slot_frames, log.slot_frames.size(),
             kSlotsFile);
  CheckCount(r, c["tag_frames"], "counts.tag_frames", counts.tag_frames, log.tag_frames.size(),
             kTagsFile);

  const YAML::Node g = root["groundtruth"];
  if (counts.trajectory_poses > 0) {
    dataset.groundtruth_trajectory = ReadTum(dir / kTrajectoryFile);
    CheckCount(r, g["trajectory_poses"], "groundtruth.trajectory_poses", counts.trajectory_poses,
               dataset.groundtruth_trajectory.size(), kTrajectoryFile);
  }
  if (counts.map) dataset.groundtruth_map = ReadMap(dir / kMapFile);
  if (counts.slot_label_frames > 0) {
    const fs::path labels_file = dir / kLabelsFile;
    const std::vector<LabelFrame> frames = ReadJsonl<LabelFrame>(labels_file, ParseLabelFrame);
    CheckCount(r, g["slot_label_frames"], "groundtruth.slot_label_frames", counts.slot_label_frames,
               frames.size(), kLabelsFile);
    dataset.slot_labels = MatchLabels(frames, dataset, labels_file.string());
  }
  return dataset;
}

namespace {

StreamSummary Summarize(const std::string& name, std::vector<TimeNs> t_ns) {
  StreamSummary s;
  s.name = name;
  s.count = t_ns.size();
  if (t_ns.empty()) return s;
  std::sort(t_ns.begin(), t_ns.end());
  s.first_s = ToSeconds(t_ns.front());
  s.last_s = ToSeconds(t_ns.back());
  std::vector<double> periods;
  for (size_t i = 1; i < t_ns.size(); ++i) {
    const double gap = ToSeconds(t_ns[i] - t_ns[i - 1]);
    periods.push_back(gap);
    if (gap > s.max_gap_s) {
      s.max_gap_s = gap;
      s.max_gap_after_s = ToSeconds(t_ns[i - 1]);
    }
  }
  if (!periods.empty()) {
    // The lower median: with two periods, one of them a gap, the gap must
    // not set the stream's period.
    const size_t middle = (periods.size() - 1) / 2;
    std::nth_element(periods.begin(), periods.begin() + static_cast<long>(middle), periods.end());
    s.median_period_s = periods[middle];
  }
  return s;
}

template <typename Samples>
std::vector<TimeNs> Times(const Samples& samples) {
  std::vector<TimeNs> t;
  for (const auto& sample : samples) t.push_back(sample.t_ns);
  return t;
}

// The first bytes of a file: enough for any image header.
std::string FileHead(const fs::path& path) {
  CheckInputFile(path, kMaxImageBytes);  // no FIFO, device or huge file
  std::ifstream in(path, std::ios::binary);
  std::string bytes(1 << 16, '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  bytes.resize(static_cast<size_t>(in.gcount()));
  return bytes;
}

// Runs one read or check; a failure becomes one of the check's errors.
template <typename F>
bool Attempt(DatasetCheck* check, F&& f) {
  try {
    f();
    return true;
  } catch (const std::exception& e) {
    check->errors.push_back(e.what());
    return false;
  }
}

void CheckImages(const fs::path& dir, DatasetCheck* check) {
  const auto attempt = [check](auto&& f) { return Attempt(check, f); };
  std::vector<ImageIndexEntry> index;
  std::optional<camera::CameraRig> rig;
  attempt([&] { index = ReadImageIndex(dir); });
  attempt([&] { rig = LoadRig(dir / "images" / "rig.yaml"); });
  std::map<std::string, std::vector<TimeNs>> times;
  for (const ImageIndexEntry& entry : index) {
    times[entry.camera].push_back(entry.t_ns);
    attempt([&] {
      const fs::path path = dir / entry.file;
      const cv::Size size = ImageSizeFromHeader(FileHead(path), path.string());
      CheckImageEnds(path);
      const camera::CameraConfig* camera = rig ? rig->Find(entry.camera) : nullptr;
      if (rig && camera == nullptr) {
        ThrowIoError(path.string(), 0, "",
                     "camera '" + entry.camera + "' is not in images/rig.yaml");
      }
      if (camera != nullptr &&
          (size.width != camera->intrinsics.width || size.height != camera->intrinsics.height)) {
        ThrowIoError(path.string(), 0, "",
                     std::to_string(size.width) + " x " + std::to_string(size.height) +
                         " pixels, but images/rig.yaml gives camera '" + entry.camera + "' " +
                         std::to_string(camera->intrinsics.width) + " x " +
                         std::to_string(camera->intrinsics.height));
      }
    });
  }
  for (const auto& [camera, t] : times) {
    check->streams.push_back(Summarize("images/index.csv (" + camera + ")", t));
  }
}

// Ground truth as ReadDataset reads it for the eval commands: the
// trajectory (finite poses, strictly increasing times), the map, the labels
// matched to the slot frames, and their counts against dataset.yaml.
void CheckGroundTruth(const fs::path& dir, const std::optional<Counts>& counts,
                      const SensorLog& log, bool slots_read, DatasetCheck* check) {
  if (!counts) return;
  const auto attempt = [check](auto&& f) { return Attempt(check, f); };
  const fs::path manifest = dir / kDatasetManifestFile;
  const auto count = [&](const char* file, std::int64_t announced, std::size_t held) {
    if (announced == static_cast<std::int64_t>(held)) return;
    check->errors.push_back(manifest.string() + ": groundtruth: " + std::to_string(announced) +
                            " announced for " + file + ", which holds " + std::to_string(held));
  };
  if (counts->trajectory_poses > 0) {
    attempt([&] {
      count(kTrajectoryFile, counts->trajectory_poses, ReadTum(dir / kTrajectoryFile).size());
    });
  }
  Dataset truth;
  const bool map_read =
      !counts->map || attempt([&] { truth.groundtruth_map = ReadMap(dir / kMapFile); });
  if (counts->slot_label_frames > 0 && slots_read && map_read) {
    attempt([&] {
      const fs::path labels_file = dir / kLabelsFile;
      const std::vector<LabelFrame> frames = ReadJsonl<LabelFrame>(labels_file, ParseLabelFrame);
      count(kLabelsFile, counts->slot_label_frames, frames.size());
      truth.log.slot_frames = log.slot_frames;
      MatchLabels(frames, truth, labels_file.string());
    });
  }
}

// The streams of one drive start and end together: one that runs on for an
// hour after the others (or starts long before) is two recordings, or a
// clock that jumped, and would leave the car dead reckoning on one sensor.
std::vector<std::string> StreamsApart(const fs::path& dir,
                                      const std::vector<StreamSummary>& streams) {
  std::vector<std::string> errors;
  std::vector<double> firsts, lasts;
  for (const StreamSummary& s : streams) {
    if (s.count == 0) continue;
    firsts.push_back(s.first_s);
    lasts.push_back(s.last_s);
  }
  if (firsts.size() < 2) return errors;
  const auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  const double first_s = median(firsts), last_s = median(lasts);
  for (const StreamSummary& s : streams) {
    if (s.count == 0) continue;
    const double early_s = first_s - s.first_s, late_s = s.last_s - last_s;
    if (early_s <= kMaxStreamSkew_s && late_s <= kMaxStreamSkew_s) continue;
    char line[320];
    std::snprintf(line, sizeof line,
                  "%s: runs from %.3f s to %.3f s, but the other streams from about %.3f s to "
                  "%.3f s (the streams of one drive start and end within %.0f s of each other)",
                  (dir / s.name).string().c_str(), s.first_s, s.last_s, first_s, last_s,
                  kMaxStreamSkew_s);
    errors.push_back(line);
  }
  return errors;
}

}  // namespace

DatasetCheck CheckDataset(const fs::path& dir, double max_gap_s) {
  DatasetCheck check;
  const auto attempt = [&check](auto&& f) { return Attempt(&check, f); };
  std::error_code error;
  if (!fs::is_directory(dir, error)) {
    check.errors.push_back(dir.string() + ": not a folder");
    return check;
  }
  const fs::path manifest = dir / kDatasetManifestFile;
  std::optional<Counts> counts;
  YAML::Node root;
  attempt([&] {
    root = LoadManifest(dir);
    Dataset unused;
    counts = ReadManifest(root, YamlReader(manifest.string(), true), &unused);
  });

  SensorLog log;
  const bool wheel = attempt([&] { log.wheel_speeds = ReadWheelSpeeds(dir); });
  const bool steering = attempt([&] { log.steering_angles = ReadSteeringAngles(dir); });
  const bool imu = attempt([&] { log.imu_samples = ReadImuSamples(dir); });
  const bool slots = attempt([&] { log.slot_frames = ReadSlotFrames(dir); });
  const bool tags = attempt([&] { log.tag_frames = ReadTagFrames(dir); });

  const auto stream = [&](bool read, const char* file, std::vector<TimeNs> t,
                          std::int64_t announced) {
    if (!read) return;
    check.streams.push_back(Summarize(file, std::move(t)));
    if (counts && announced != static_cast<std::int64_t>(check.streams.back().count)) {
      check.errors.push_back(manifest.string() + ": counts: " + std::to_string(announced) +
                             " announced for " + file + ", which holds " +
                             std::to_string(check.streams.back().count));
    }
  };
  stream(wheel, kWheelSpeedFile, Times(log.wheel_speeds), counts ? counts->wheel_speed : 0);
  stream(steering, kSteeringFile, Times(log.steering_angles), counts ? counts->steering : 0);
  stream(imu, kImuFile, Times(log.imu_samples), counts ? counts->imu : 0);
  stream(slots, kSlotsFile, Times(log.slot_frames), counts ? counts->slot_frames : 0);
  stream(tags, kTagsFile, Times(log.tag_frames), counts ? counts->tag_frames : 0);
  if (fs::exists(dir / "images", error)) CheckImages(dir, &check);

  CheckGroundTruth(dir, counts, log, slots, &check);
  for (std::string& e : StreamsApart(dir, check.streams)) check.errors.push_back(std::move(e));

  for (const StreamSummary& s : check.streams) {
    // A stream slower than the limit (images at 0.5 Hz, say) is judged by
    // its own period: a missing sample is a gap of two.
    const double limit = std::max(max_gap_s, 1.5 * s.median_period_s);
    if (s.max_gap_s > limit) {
      char line[256];
      std::snprintf(line, sizeof line, "%s: a gap of %.2f s after t = %.3f s (more than %.2f s)",
                    (dir / s.name).string().c_str(), s.max_gap_s, s.max_gap_after_s, limit);
      check.errors.push_back(line);
    }
  }
  return check;
}

}  // namespace parkslam::io
