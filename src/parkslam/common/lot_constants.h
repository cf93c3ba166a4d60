#ifndef PARKSLAM_COMMON_LOT_CONSTANTS_H_
#define PARKSLAM_COMMON_LOT_CONSTANTS_H_

// Sizes of the lot that several modules assume by default, defined once.

namespace parkslam {

// Edge of an AprilTag's black square (the paper's tags; every default of
// the map, the simulator, the detector and the mapper).
inline constexpr double kDefaultTagSize_m = 0.488;

// Depth of a standard perpendicular slot: the far corners a detector does
// not see are guessed this far behind the entrance line (paper III-A).
inline constexpr double kStandardSlotDepth_m = 5.3;

}  // namespace parkslam

#endif  // PARKSLAM_COMMON_LOT_CONSTANTS_H_
