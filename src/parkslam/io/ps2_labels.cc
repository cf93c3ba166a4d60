#include "parkslam/io/ps2_labels.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "parkslam/common/angles.h"
#include "parkslam/common/plausible_ranges.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/io_error.h"
#include "parkslam/io/json_util.h"

namespace parkslam::io {
namespace {

using json_util::Json;
using json_util::JsonPath;
using json_util::JsonReader;

constexpr std::size_t kMarkFields = 5;  // x, y, dx, dy, shape
constexpr std::size_t kSlotFields = 4;  // i, j, type, angle

// DMPR-PS's labels store a list of one mark or one slot flat: [a, b, ...]
// instead of [[a, b, ...]]. A list whose first element is not an array is
// that single entry; its elements are then checked as the entry's fields,
// so a nested list with a stray number still fails, at the number.
bool IsFlat(const Json& list) { return !list.empty() && !list[0].is_array(); }

std::vector<const Json*> Entries(const Json& list, const JsonReader& r, const JsonPath& path) {
  r.ExpectArray(list, path);
  std::vector<const Json*> entries;
  if (IsFlat(list)) {
    entries.push_back(&list);
  } else {
    for (const Json& entry : list) entries.push_back(&entry);
  }
  return entries;
}

Ps2MarkingPoint ReadMark(const Json& j, const JsonReader& r, const JsonPath& path) {
  r.ExpectArray(j, path, kMarkFields, "numbers [x, y, dx, dy, shape]");
  double values[kMarkFields];
  for (std::size_t k = 0; k < kMarkFields; ++k) {
    const JsonPath field = path.Index(k);
    // Pixels but for the shape, checked below.
    values[k] =
        k < 4 ? r.BoundedNumber(j[k], field, kMaxPixelCoordinate_px, "px") : r.Number(j[k], field);
  }
  const Eigen::Vector2d p(values[0], values[1]);
  const Eigen::Vector2d along(values[2], values[3]);
  if (along == p) r.Fail(path, "the separating-line point [dx, dy] equals [x, y]: no direction");
  const double shape = values[4];
  if (shape != 0.0 && shape != 1.0) {
    const JsonPath shape_path = path.Index(4);
    r.Fail(shape_path, "expected 0 (T) or 1 (L), got " + j[4].dump());
  }
  Ps2MarkingPoint mark;
  mark.px = p - Eigen::Vector2d::Constant(kPs2LabelOffsetPx);
  const Eigen::Vector2d direction = along - p;
  mark.direction_rad = std::atan2(direction.y(), direction.x());
  mark.is_t = shape == 0.0;
  return mark;
}

// A 1-based index into `mark_count` marks, returned 0-based.
int ReadMarkIndex(const Json& j, const JsonReader& r, const JsonPath& path,
                  std::size_t mark_count) {
  const double value = r.Number(j, path);
  if (std::floor(value) != value || value < 1.0 || value > static_cast<double>(mark_count)) {
    r.Fail(path, "expected a 1-based index into marks (1 to " + std::to_string(mark_count) +
                     "), got " + j.dump());
  }
  return static_cast<int>(value) - 1;
}

Ps2Slot ReadSlot(const Json& j, const JsonReader& r, const JsonPath& path, std::size_t mark_count) {
  r.ExpectArray(j, path, kSlotFields, "numbers [i, j, type, angle]");
  const JsonPath a_path = path.Index(0);
  const JsonPath b_path = path.Index(1);
  const JsonPath type_path = path.Index(2);
  const JsonPath angle_path = path.Index(3);
  Ps2Slot slot;
  slot.a = ReadMarkIndex(j[0], r, a_path, mark_count);
  slot.b = ReadMarkIndex(j[1], r, b_path, mark_count);
  // Not used, but a label is read whole or not at all.
  r.Number(j[2], type_path);
  r.BoundedNumber(j[3], angle_path, kMaxAngle_deg, "deg");
  if (slot.a == slot.b) {
    r.Fail(path, "both ends of the entrance are mark " + std::to_string(slot.a + 1));
  }
  return slot;
}

double AngleOf(const Eigen::Vector2d& v) { return std::atan2(v.y(), v.x()); }

// For each slot end that is an L, with the other end: the image angle from
// the L towards its partner (the entrance arm). The first slot of an L
// decides; an L is the end of a row and ends one slot.
struct LEnd {
  std::size_t mark = 0;
  std::size_t partner = 0;
  double entrance_rad = 0.0;
};

std::vector<LEnd> LEndsOf(const Ps2Labels& labels) {
  std::vector<LEnd> ends;
  std::vector<bool> seen(labels.marking_points.size(), false);
  for (const Ps2Slot& s : labels.slots) {
    const auto a = static_cast<std::size_t>(s.a), b = static_cast<std::size_t>(s.b);
    for (const auto& [mark, partner] : {std::pair{a, b}, std::pair{b, a}}) {
      if (labels.marking_points[mark].is_t || seen[mark]) continue;
      seen[mark] = true;
      const Eigen::Vector2d to_partner =
          labels.marking_points[partner].px - labels.marking_points[mark].px;
      ends.push_back({mark, partner, AngleOf(to_partner)});
    }
  }
  return ends;
}

// DMPR-PS's L directions to separating lines (the header's rule). The
// partners' directions are read before any is changed.
void ToSeparatingLines(Ps2Labels* labels) {
  const std::vector<LEnd> ends = LEndsOf(*labels);
  std::vector<double> labelled(labels->marking_points.size());
  for (std::size_t i = 0; i < labelled.size(); ++i)
    labelled[i] = labels->marking_points[i].direction_rad;
  for (const LEnd& e : ends) {
    if (std::abs(AngleDiff(e.entrance_rad, labelled[e.mark])) > kPs2EntranceArmTolerance_rad) {
      continue;  // labelled along its separating line already
    }
    const double partner_rad = labelled[e.partner];
    const bool partner_along_entrance =
        std::abs(AngleDiff(e.entrance_rad + kPi, partner_rad)) <= kPs2EntranceArmTolerance_rad;
    labels->marking_points[e.mark].direction_rad =
        partner_along_entrance ? NormalizeAngle(labelled[e.mark] + kPi / 2) : partner_rad;
  }
}

}  // namespace

Ps2Labels Ps2LabelsFromJson(const nlohmann::json& json, const std::string& source_name) {
  const JsonReader r(source_name, 0);
  const JsonPath root;
  r.ExpectObject(json, root, {"marks", "slots"});
  Ps2Labels labels;
  const JsonPath marks = root.Key("marks");
  const std::vector<const Json*> mark_entries = Entries(json["marks"], r, marks);
  const bool flat_marks = IsFlat(json["marks"]);
  for (std::size_t i = 0; i < mark_entries.size(); ++i) {
    // A flat single mark is reported as "marks", its fields as "marks[k]";
    // likewise a flat single slot.
    const JsonPath mark = marks.Index(i);
    labels.marking_points.push_back(ReadMark(*mark_entries[i], r, flat_marks ? marks : mark));
  }
  const JsonPath slots = root.Key("slots");
  const std::vector<const Json*> slot_entries = Entries(json["slots"], r, slots);
  const bool flat_slots = IsFlat(json["slots"]);
  for (std::size_t i = 0; i < slot_entries.size(); ++i) {
    const JsonPath slot = slots.Index(i);
    labels.slots.push_back(
        ReadSlot(*slot_entries[i], r, flat_slots ? slots : slot, labels.marking_points.size()));
  }
  ToSeparatingLines(&labels);
  return labels;
}

nlohmann::json Ps2LabelsToJson(const Ps2Labels& labels) {
  // DMPR-PS's convention: an L whose entrance leaves at a negative angle
  // from its separating line is labelled along the entrance.
  std::vector<double> labelled(labels.marking_points.size());
  for (std::size_t i = 0; i < labelled.size(); ++i)
    labelled[i] = labels.marking_points[i].direction_rad;
  for (const LEnd& e : LEndsOf(labels)) {
    if (AngleDiff(e.entrance_rad, labelled[e.mark]) < 0.0) labelled[e.mark] = e.entrance_rad;
  }
  nlohmann::json marks = nlohmann::json::array();
  for (std::size_t i = 0; i < labels.marking_points.size(); ++i) {
    const Ps2MarkingPoint& m = labels.marking_points[i];
    const double x = m.px.x() + kPs2LabelOffsetPx, y = m.px.y() + kPs2LabelOffsetPx;
    marks.push_back({x, y, x + kPs2DirectionLengthPx * std::cos(labelled[i]),
                     y + kPs2DirectionLengthPx * std::sin(labelled[i]), m.is_t ? 0 : 1});
  }
  nlohmann::json slots = nlohmann::json::array();
  for (const Ps2Slot& s : labels.slots) slots.push_back({s.a + 1, s.b + 1, s.type, s.angle_deg});
  return nlohmann::json{{"marks", marks}, {"slots", slots}};
}

Ps2Labels ReadPs2Labels(const std::filesystem::path& json_path) {
  const std::string text = ReadTextFile(json_path, kMaxJsonBytes);
  const Json json = json_util::ParseJson(text, json_path.string(), 0);
  return Ps2LabelsFromJson(json, json_path.string());
}

std::vector<std::string> ListPs2Images(const std::filesystem::path& folder) {
  namespace fs = std::filesystem;
  std::error_code list_error;
  fs::directory_iterator it(folder, list_error);
  std::vector<std::string> names;
  while (!list_error && it != fs::directory_iterator()) {
    const fs::path& path = it->path();
    fs::path label = path;
    label.replace_extension(".json");
    std::error_code ignored;
    if (path.extension() == ".jpg" && fs::exists(label, ignored)) {
      // A labelled image whose image or labels is a folder, FIFO or device
      // (a link to /dev/zero) is refused, not left out of the score.
      for (const fs::path& file : {path, label}) {
        if (!fs::is_regular_file(file, ignored)) {
          ThrowIoError(file.string(), 0, "",
                       "not a plain file (a folder, FIFO, device or broken link); a labelled "
                       "view is a plain .jpg and a plain .json");
        }
      }
      names.push_back(path.stem().string());
    }
    it.increment(list_error);
  }
  if (list_error) {
    ThrowIoError(folder.string(), 0, "", "cannot list the folder: " + list_error.message());
  }
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace parkslam::io
