#ifndef PARKSLAM_MAPPING_MAP_GRAPH_H_
#define PARKSLAM_MAPPING_MAP_GRAPH_H_

// The mapper's factor graph (paper III-C, Fig. 4): keyframe poses tied by
// odometry factors, slot corners by Max-Mixture corner factors (one per
// slot observation, over all its candidates and a null hypothesis) and the
// rectangular shape factor of each slot, tag poses by tag observation
// factors. Built over the map state, solved with Ceres, and read back:
// the optimized poses, corners and tags are written into the state, and
// the records whose mixture now picks another component are reported, for
// slot management to move their evidence.

#include <array>
#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "parkslam/mapping/map_state.h"
#include "parkslam/mapping/mapper_options.h"

namespace parkslam::mapping {

struct MapGraphSolve {
  int residual_blocks = 0;
  int iterations = 0;
  double final_cost = 0.0;
  // A record whose mixture picks another slot at the solution than the
  // one it had chosen (-1: the null hypothesis), in record order.
  struct Choice {
    size_t record = 0;
    int before = -1, after = -1;
  };
  std::vector<Choice> changed;
};

// Solves over the keyframes from first_free on (earlier ones held fixed,
// and always the first, the map's anchor) and the landmarks they see.
// With `final` every record of a free landmark enters; otherwise only the
// latest window_history_observations of each beside the window's own, so
// that a windowed solve stays bounded however long the drive. Does not
// change the records' choices. Throws std::runtime_error when Ceres fails.
MapGraphSolve SolveMapGraph(MapState* state, int first_free, int max_iterations, bool final,
                            const MapperOptions& options);

// The marginal covariance of each corner that the map will show as seen (of
// a live slot with MapperOptions::min_observations) in the full graph at the
// state's present values (every keyframe and record in), m^2, by slot index
// of the state, relative to the map as a whole: the gauge is the rigid
// motion of those corners together, not the first keyframe. Every other
// corner gets std::nullopt. It holds the drive's own uncertainty: drift
// between loop closures, how often and how well each corner was seen.
// Returns false, filling nothing, when Ceres cannot compute it (a graph that
// leaves more than its gauge free), when fewer than two corners were seen,
// or more than 2,000 (the joint covariance is dense: 128 MB at that size).
using CornerCovariances = std::vector<std::array<std::optional<Eigen::Matrix2d>, kSlotCorners>>;
bool ComputeCornerCovariances(MapState* state, const MapperOptions& options,
                              CornerCovariances* covariances);

}  // namespace parkslam::mapping

#endif  // PARKSLAM_MAPPING_MAP_GRAPH_H_
