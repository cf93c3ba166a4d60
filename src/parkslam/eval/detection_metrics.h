#ifndef PARKSLAM_EVAL_DETECTION_METRICS_H_
#define PARKSLAM_EVAL_DETECTION_METRICS_H_

// Quality of a parking-slot detector in single top-view images, against
// labelled images (the ps2.0 data set) or the simulator's truth: marking
// points and slots found, missed and invented (precision and recall), how
// far the matched slots' corners lie from the truth, and how many carry the
// right painted ID.
//
// The match rule is the one of DMPR-PS (Huang et al., "DMPR-PS: A Novel
// Approach for Parking-Slot Detection Using Directional Marking-Point
// Regression", ICME 2019; its evaluation code, data/struct.py):
//  - a detected marking point matches a labelled one when their positions
//    lie within max_distance_px (10 px in a 600 x 600 image, i.e. 1/60 of
//    the image) and their directions within max_direction_difference_rad
//    (30 degrees), the direction difference wrapped into [0, pi]; the shape
//    (T or L) is not compared unless require_same_shape;
//  - a detected slot matches a labelled one when both ends of its entrance
//    line lie within max_distance_px of the labelled slot's two marking
//    points. DMPR-PS compares the ends in the order stored; here either
//    order is accepted (the detector and the labels need not agree on which
//    end comes first), which reports the swap.
// "Within" means distance <= threshold. DMPR-PS tests a squared normalised
// distance < 0.000277778 (that is, < 10.000004 px) and an angle < 30
// degrees: the same except on the boundary itself.
//
// Matching is one to one (DMPR-PS lets one detection absorb several labels;
// here a second label near the same detection is a false negative): all
// admissible (detected, true) pairs are taken greedily by increasing
// distance (for a slot, the larger of its two end distances), ties broken by
// the lower detected index, then the lower true index. Greedy is not
// optimal in general, but labelled marking points lie far further apart
// (> 40 px) than twice the match radius, so each detection can only match
// one label and greedy equals the optimal matching on such data; where it
// matters (two detections near one label), the nearer wins and the other is
// a false positive (a duplicate).
//
// Top-view pixels are 0-based, (0, 0) the centre of the top-left pixel, x to
// the right, y down (camera/top_view.h); directions are image angles
// atan2(dy, dx) in that frame. This module depends on no detector: callers
// convert their detections into the plain structs below.

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

namespace parkslam::eval {

// A marking point, detected or labelled.
struct LabelledMarkingPoint {
  Eigen::Vector2d px = Eigen::Vector2d::Zero();
  // Image angle atan2(dy, dx) of the separating line leaving the point.
  double direction_rad = 0.0;
  bool is_t = true;  // T-shaped, else L-shaped
};

// A labelled slot as the indices of its two entrance marking points.
struct LabelledSlot {
  int a = 0;
  int b = 0;
};

// A slot's entrance line by its two ends (slot corners 0 and 1 in the
// project's corner order, sensor/sensor_data.h).
struct EntranceLine {
  Eigen::Vector2d a_px = Eigen::Vector2d::Zero();
  Eigen::Vector2d b_px = Eigen::Vector2d::Zero();
};

// The four corners of a slot in the project's order: 0-1 the entrance, 2
// behind 1, 3 behind 0.
using SlotCornersPx = std::array<Eigen::Vector2d, 4>;

struct DetectionMatchOptions {
  double max_distance_px = 10.0;
  double max_direction_difference_rad = 0.5235987755982988;  // 30 degrees
  // DMPR-PS does not compare shapes; set to count a T detected as an L as
  // a miss and a false positive.
  bool require_same_shape = false;

  // False, naming the field, when a threshold is not positive and finite.
  bool IsValid(std::string* error) const;
};

// The entrance lines of labelled slots. Throws std::invalid_argument when an
// index is out of range.
std::vector<EntranceLine> EntranceLinesOf(const std::vector<LabelledMarkingPoint>& points,
                                          const std::vector<LabelledSlot>& slots);

// |a - b| wrapped into [0, pi]: 359 degrees and 1 degree differ by 2.
double DirectionDifferenceRad(double a_rad, double b_rad);

// The match rule for one pair (see the top of this file); false when any
// coordinate or angle is not finite.
bool MarkingPointsMatch(const LabelledMarkingPoint& detected, const LabelledMarkingPoint& truth,
                        const DetectionMatchOptions& options = {});
// True when the ends match in the given order or swapped; *swapped (may be
// null) tells which. When both orders match (an entrance shorter than twice
// the radius), the one with the smaller larger end distance wins, the given
// order on a tie.
bool EntranceLinesMatch(const EntranceLine& detected, const EntranceLine& truth,
                        const DetectionMatchOptions& options = {}, bool* swapped = nullptr);

struct DetectionPair {
  int detected = 0;          // index into the detections
  int truth = 0;             // index into the truth
  double distance_px = 0.0;  // for a slot, the larger of its two end distances
  // Slots only: the detection's entrance ends match the truth's swapped
  // (detected a ~ truth b), so its corners 0, 1, 2, 3 correspond to the
  // truth's 1, 0, 3, 2.
  bool swapped = false;
};

// A one-to-one matching of detections to the truth.
struct DetectionMatch {
  std::vector<DetectionPair> pairs;    // in the order they were chosen
  std::vector<int> truth_of_detected;  // per detection: matched truth index, -1 none
  std::vector<int> detected_of_truth;  // per truth item: matched detection, -1 none

  int true_positives() const { return static_cast<int>(pairs.size()); }
  // Detections matching nothing, duplicates included.
  int false_positives() const {
    return static_cast<int>(truth_of_detected.size()) - true_positives();
  }
  int false_negatives() const {
    return static_cast<int>(detected_of_truth.size()) - true_positives();
  }
};

// Throw std::invalid_argument on invalid options.
DetectionMatch MatchMarkingPoints(const std::vector<LabelledMarkingPoint>& detected,
                                  const std::vector<LabelledMarkingPoint>& truth,
                                  const DetectionMatchOptions& options = {});
DetectionMatch MatchSlots(const std::vector<EntranceLine>& detected,
                          const std::vector<EntranceLine>& truth,
                          const DetectionMatchOptions& options = {});

// True positives, false positives and false negatives summed over images.
struct DetectionCounts {
  int true_positives = 0;
  int false_positives = 0;
  int false_negatives = 0;

  void Add(const DetectionMatch& match);
  void Add(const DetectionCounts& other);
  // TP / (TP + FP); 1 when nothing was detected (no detection is wrong).
  double precision() const;
  // TP / (TP + FN); 1 when there was nothing to find (nothing was missed).
  double recall() const;
};

// Count, mean, root mean square and maximum of non-negative errors; all 0
// while empty.
struct ErrorAccumulator {
  int count = 0;
  double sum = 0.0;
  double sum_squares = 0.0;
  double max = 0.0;

  void Add(double error);
  void Add(const ErrorAccumulator& other);
  double mean() const;
  double rms() const;
};

// Corner errors of matched slots, metres.
struct SlotCornerErrors {
  ErrorAccumulator entrance_m;     // corners 0 and 1 (the marking points)
  ErrorAccumulator all_corners_m;  // all four (2 and 3 may be guessed)
};

// Adds, for every pair of `match` (from MatchSlots), the distance between
// each detected corner and the truth's corresponding corner (index by
// index, or 1, 0, 3, 2 when the pair is swapped), divided by pixels_per_m.
// Throws std::invalid_argument when the corner lists do not have one entry
// per detection and per truth slot of `match`, or when pixels_per_m is not
// positive and finite.
void AddSlotCornerErrors(const DetectionMatch& match, const std::vector<SlotCornersPx>& detected,
                         const std::vector<SlotCornersPx>& truth, double pixels_per_m,
                         SlotCornerErrors* errors);

// The painted ID of a true slot.
struct SlotIdTruth {
  std::string id;  // "" when none is painted
  // False when the paint is worn or hidden: no reader could read it. An
  // empty id is never readable.
  bool readable = true;
};

// ID reading over matched slots. A detected ID is the reader's full best
// guess ("" when nothing was read, '?' for an unread digit, as
// SlotIdReading::best()); it is right only when it equals the truth's ID
// character for character, so a partial ("3?") or missing reading of a
// readable ID is wrong.
struct IdCounts {
  int readable = 0;    // matched slots whose truth ID is readable
  int correct = 0;     // of those, the detected ID equals it
  int unread = 0;      // of those, no ID was read at all (counted wrong)
  int unreadable = 0;  // matched slots whose truth has no readable ID
  // Of those, a whole ID (no unread digit) was read anyway: what a mapper
  // would take as the slot's name. A partial reading ("3?") is not counted.
  int invented = 0;
  int invented_right = 0;  // of those, the painted ID itself (worn paint read right)

  void Add(const IdCounts& other);
  // correct / readable; 1 when no matched slot had a readable ID.
  double accuracy() const;
};

// Adds the pairs of `match` (from MatchSlots) to *counts. Throws
// std::invalid_argument when the ID lists do not have one entry per
// detection and per truth slot of `match`.
void AddIdCounts(const DetectionMatch& match, const std::vector<std::string>& detected_ids,
                 const std::vector<SlotIdTruth>& truth_ids, IdCounts* counts);

}  // namespace parkslam::eval

#endif  // PARKSLAM_EVAL_DETECTION_METRICS_H_
