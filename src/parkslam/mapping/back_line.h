#ifndef PARKSLAM_MAPPING_BACK_LINE_H_
#define PARKSLAM_MAPPING_BACK_LINE_H_

// The far corners of a map's slots, and how sure the map is of them.
//
// The detector sees a slot's entrance well and its back line rarely; a far
// corner it never saw is guessed at the standard depth (paper III-A: "the
// parking slot can only be guessed"). Real rows differ in depth (4.8 to
// 6.2 m in real garages' plans), so such a guess can be off by most of a
// metre. Neighbours in a row share their separating lines, and a row has one
// depth, so what one slot saw of the back line serves its neighbours:
//
//   1. A far corner that one slot never saw but its neighbour did (the far
//      end of the separating line they share) is the neighbour's corner,
//      with its sigma: it was seen.
//   2. A slot that saw one of its far corners (directly or as in 1) knows
//      its depth and side direction: the other far corner follows from its
//      entrance corner, with the seen corner's sigma and within_slot_sigma_m.
//   3. A slot that saw neither takes the side vector (depth and angle, in the
//      frame of its entrance line) of the nearest slot of its row that saw
//      one, with row_depth_sigma_m.
//   4. A slot alone with its guess keeps it, with depth_prior_sigma_m: the
//      spread of real slots' depths, not the detector's noise.
//
// Corners of 2-4 stay unobserved (corner_observed false). Parallel slots
// share no separating line with a neighbour and only take step 2.

#include <vector>

#include "parkslam/map/semantic_map.h"

namespace parkslam::mapping {

struct BackLineOptions {
  // Two slots are neighbours in a row when one's corner 1 lies this close to
  // the other's corner 0 and their entrance lines point the same way.
  double neighbour_corner_m = 0.5;
  double neighbour_angle_rad = 0.1;
  double within_slot_sigma_m = 0.05;
  double row_depth_sigma_m = 0.05;
  double depth_prior_sigma_m = 0.4;
};

// What ShareBackLines did, by step.
struct BackLineStats {
  int shared_corners = 0;  // step 1
  int from_own_side = 0;   // step 2
  int from_row = 0;        // step 3
  int guessed = 0;         // step 4
};

// Fills in the far corners (2 and 3) of every slot that did not see them,
// as above, and states their sigmas. Corners seen stay as they are.
BackLineStats ShareBackLines(const BackLineOptions& options, std::vector<MapSlot>* slots);

}  // namespace parkslam::mapping

#endif  // PARKSLAM_MAPPING_BACK_LINE_H_
