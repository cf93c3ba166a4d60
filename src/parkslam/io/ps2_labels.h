#ifndef PARKSLAM_IO_PS2_LABELS_H_
#define PARKSLAM_IO_PS2_LABELS_H_

// The labels of the ps2.0 parking-slot data set (Tongji University), in the
// JSON form of DMPR-PS, one file per 600 x 600 top-view image:
//
// {"marks": [[x, y, dx, dy, shape], ...],   marking points
//  "slots": [[i, j, type, angle], ...]}     slots by their entrance line
//
// x, y: the marking point in 1-based pixel coordinates; subtracting
// kPs2LabelOffsetPx (0.5, as the data folder's README and DMPR-PS's own
// prepare_dataset.py and ps_evaluate.py do) gives the 0-based coordinates
// used here. dx, dy: a point along one arm of the marking point (same
// coordinates), so the labelled direction is atan2(dy - y, dx - x) in the
// image (y down). shape: 0 T-shaped, 1 L-shaped. i, j: 1-based indices into
// marks, the two ends of one slot's entrance line; type and angle are not
// used. A file with a single mark or a single slot stores it as a flat list
// ("slots": [2, 1, 1, 90]) rather than a list of one list.
//
// Which arm (DMPR-PS's convention, as every label of the real sample
// follows it). A T's direction is its separating line. An L has two arms,
// and its direction is the one from which the other arm turns by a positive
// image angle (clockwise on screen, y down): the separating line where the
// entrance line leaves on that side, else the entrance line itself. In a
// slot [i, j], the entrance from i to j lies at +90 degrees from i's
// separating line, so an L at i is labelled along its separating line and
// an L at j along the entrance, towards i (7 of the sample's 11 L's, within
// 2 degrees). parkslam's marking points always carry their separating line
// (the pairing needs it), so:
// - reading, an L that is one end of a labelled slot and whose direction
//   lies within kPs2EntranceArmTolerance_rad of the way to its partner
//   takes the partner's direction (the parallel separating line; a
//   partner labelled along the entrance too gives the labelled direction
//   plus 90 degrees, the convention's other arm);
// - writing, an L that is one end of a slot and whose entrance leaves at a
//   negative angle from its separating line is written along the entrance,
//   towards its partner.
// An L in no labelled slot keeps its labelled direction: the label alone
// does not say which arm it names.
//
// Reading is strict: both keys and nothing else, every mark 5 finite
// numbers, its pixels within kMaxPixelCoordinate_px and its shape 0 or 1, a
// separating-line point distinct from its marking point, every slot 4
// numbers with integral indices in range, two different ends and an angle
// within kMaxAngle_deg (common/plausible_ranges.h).

#include <Eigen/Core>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace parkslam::io {

// 1-based label coordinates minus this are the 0-based top-view pixels.
inline constexpr double kPs2LabelOffsetPx = 0.5;
// An L labelled within this of the way to its slot partner names its
// entrance arm. Separating lines leave the entrance at 40 degrees or more
// (angled rows), labels along the entrance lie within 2 degrees of it.
inline constexpr double kPs2EntranceArmTolerance_rad = 0.35;  // 20 degrees
// ps2.0 images are this many pixels square, for about 10 m.
inline constexpr int kPs2ImageSizePx = 600;

struct Ps2MarkingPoint {
  Eigen::Vector2d px = Eigen::Vector2d::Zero();  // 0-based top-view pixels
  // Image angle atan2(dy, dx) of the separating line leaving the point (for
  // an L labelled along its entrance, converted as the header says).
  double direction_rad = 0.0;
  bool is_t = true;  // shape 0: T-shaped; shape 1: L-shaped
};

// One slot: 0-based indices into Ps2Labels::marking_points of the two ends
// of its entrance line, in the order labelled.
struct Ps2Slot {
  int a = 0;
  int b = 0;
  int type = 1;             // written as labelled; not read back
  double angle_deg = 90.0;  // written as labelled; not read back
};

struct Ps2Labels {
  std::vector<Ps2MarkingPoint> marking_points;
  std::vector<Ps2Slot> slots;
};

// Throws IoError naming source_name and the JSON path of the first problem
// ("marks[2][4]: expected 0 (T) or 1 (L), got 2").
Ps2Labels Ps2LabelsFromJson(const nlohmann::json& json, const std::string& source_name);

// Throws IoError naming the file when it cannot be read or is not JSON, and
// as Ps2LabelsFromJson.
Ps2Labels ReadPs2Labels(const std::filesystem::path& json_path);

// The labels in the same JSON form, always as lists of lists: 1-based
// pixels, each mark's arm point kPs2DirectionLengthPx along its labelled
// direction (DMPR-PS's convention, above), slots as [i, j, type, angle] with
// 1-based indices. Ps2LabelsFromJson reads it back to the same points and
// directions.
inline constexpr double kPs2DirectionLengthPx = 25.0;
nlohmann::json Ps2LabelsToJson(const Ps2Labels& labels);

// The names without extension ("20160725-3-1") of the .jpg images in
// `folder` that have a .json label file beside them, sorted; images without
// labels are left out. Throws IoError when the folder cannot be listed.
std::vector<std::string> ListPs2Images(const std::filesystem::path& folder);

}  // namespace parkslam::io

#endif  // PARKSLAM_IO_PS2_LABELS_H_
