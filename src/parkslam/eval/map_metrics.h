#ifndef PARKSLAM_EVAL_MAP_METRICS_H_
#define PARKSLAM_EVAL_MAP_METRICS_H_

// Quality of a semantic map against the ground-truth map (paper IV-A, Fig. 7):
// how many slots were found, missed, invented or mapped twice, how far their
// corners lie from the truth, and how many carry the right ID.

#include <array>
#include <vector>

#include "parkslam/common/se2.h"
#include "parkslam/map/semantic_map.h"

namespace parkslam::eval {

struct MapMetricsOptions {
  // A map slot matches a truth slot when their entrance midpoints (the middle
  // of corners 0-1) lie closer than this after the alignment.
  double match_radius_m = 1.0;
  // Estimate an SE(2) alignment of the map onto the truth (the map may be in
  // an odometry frame, rotated and shifted); otherwise compare as given.
  bool align = true;
  // Empty: every truth slot counts. Otherwise one flag per truth slot: which
  // count (e.g. those the car passed). Truth slots that do not count still
  // take part in the matching and absorb their map slots silently.
  std::vector<bool> truth_slot_mask;
};

// What became of one map slot, for pictures and reports.
enum class SlotVerdict { kMatched, kSpurious, kDuplicate, kNotCounted };
struct MapSlotVerdict {
  SlotVerdict verdict = SlotVerdict::kSpurious;
  int truth_slot = -1;        // matched (or, for a duplicate, nearest) truth slot
  double corner_rms_m = 0.0;  // over its 4 corners, matched slots only
  std::array<double, 4> corner_error_m = {0, 0, 0, 0};  // matched slots only
  bool id_right = false;                                // IdIsRight, matched slots only
  bool id_worn_read = false;  // right, and read where the truth calls the paint worn
};

// Corner errors of one kind of corner (observed or not) against the sigma
// the map states for them. corner_sigma_m is a per-axis standard deviation,
// so a corner lies "inside 2 sigma" when |error|^2 / sigma^2 is below the
// 2-dof chi-square quantile of the 1-D 2-sigma probability (95.45 %:
// |error| < 2.486 sigma); a calibrated map has about 95 % of them inside.
struct CornerErrors {
  int count = 0;
  double rmse_m = 0.0;
  double max_m = 0.0;
  double within_2sigma = 0.0;  // share of count
};

struct MapMetrics {
  int slots_true = 0;      // truth slots that count (mask)
  int slots_matched = 0;   // counted truth slots with a matching map slot
  int slots_missed = 0;    // counted truth slots with none
  int slots_spurious = 0;  // map slots with no truth slot within the radius
  int slots_duplicate =
      0;  // extra map slots near a counted truth slot that already has a nearer match
  // Over the 4 corners of each matched slot (index by index), after the alignment.
  double slot_corner_rmse_m = 0.0;
  double slot_corner_max_m = 0.0;
  // The same corners apart by the map's corner_observed: those a camera saw
  // and those only guessed (a far corner placed by the depth prior).
  CornerErrors observed_corners;
  CornerErrors unobserved_corners;
  // Share of matched slots whose ID is right: the truth's painted ID when it
  // is legible (and the map's ID not temporary), a temporary ID when the
  // truth has none or an illegible one, or the painted ID read right where
  // the truth calls the paint worn (also counted in ids_worn_read).
  double id_accuracy = 0.0;
  int ids_worn_read = 0;
  // Share of matched slots that carry a temporary ID.
  double temporary_id_share = 0.0;
  // Tags matched by ID; position error after the alignment.
  int tags_true = 0;
  int tags_matched = 0;
  double tag_rmse_m = 0.0;
  // Map tags with a number no truth tag has (a tag taken down, still mapped).
  int tags_not_in_truth = 0;
  // The alignment used: aligned map point = T_truth_map * map point
  // (identity when !align or when no alignment could be found).
  SE2 T_truth_map;
  // One verdict per map slot (index by index), and the counted truth slots
  // that no map slot matched.
  std::vector<MapSlotVerdict> map_slots;
  std::vector<int> missed_truth_slots;
};

// Compares a map with the truth.
//
// Alignment (when options.align): correspondences by identity (tags with equal
// IDs: their centres; slots with equal, non-empty, non-temporary IDs: their
// entrance midpoints) give a robust initial guess by RANSAC over pairs, each
// pair defining an SE(2) hypothesis (deterministic: all pairs of up to 200
// correspondences, else all pairs of an evenly spaced subset of 200),
// refined on its inliers with AlignPointSets; with fewer than 2
// correspondences the initial guess is the identity. Then, 3 times: slots are
// matched one to one and the alignment is re-estimated on the corners of all
// matched slots.
//
// Matching: greedy by increasing entrance-midpoint distance, one to one, below
// options.match_radius_m. An unmatched map slot is a duplicate when its
// nearest truth slot within the radius already has a (nearer) match, else
// spurious; both are ignored for truth slots outside the mask.
//
// Empty maps give zero rates and errors, never NaN. Throws
// std::invalid_argument when the mask is neither empty nor one flag per truth
// slot, or when match_radius_m is not positive and finite.
MapMetrics EvaluateMap(const SemanticMap& map, const SemanticMap& truth,
                       const MapMetricsOptions& options = {});

}  // namespace parkslam::eval

#endif  // PARKSLAM_EVAL_MAP_METRICS_H_
