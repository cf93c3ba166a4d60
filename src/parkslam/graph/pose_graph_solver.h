#ifndef PARKSLAM_GRAPH_POSE_GRAPH_SOLVER_H_
#define PARKSLAM_GRAPH_POSE_GRAPH_SOLVER_H_

// Least-squares solution of a planar pose graph, plain or with Max-Mixture
// loop closures (max_mixture_pose_edge_factor.h). Odometry edges (between
// consecutive ids) and pose-to-point edges are always trusted; every other
// pose edge is a loop closure and, with kMaxMixture, may be switched to its
// null hypothesis.
//
// Local minima. A Max-Mixture edge picks its component from the current
// estimate, so a batch solve from dead reckoning that has drifted far sees
// every true closure as an outlier too, and keeps the drift. The default is
// therefore incremental, as the mapper runs online: poses are added in id
// order, `incremental_step` at a time; each new pose starts from its initial
// estimate moved by the correction its predecessor received; then the graph
// so far is solved (Levenberg-Marquardt, sparse normal Cholesky). A closure
// is thus first judged against a trajectory already corrected by all earlier
// closures, where a true one has a small error and a wrong one a large one.

#include <string>
#include <vector>

#include "parkslam/graph/pose_graph.h"

namespace parkslam::graph {

enum class RobustKernel { kNone, kMaxMixture };

struct SolveOptions {
  RobustKernel robust = RobustKernel::kNone;
  // The null hypothesis of a Max-Mixture closure: its weight against the
  // edge's 1 and the scale of its information. With the defaults a closure
  // is switched off above e^T Omega e = 50.6 (NullThresholdChi2).
  double null_weight = 1e-2;
  double null_information_scale = 1e-6;
  // Poses added between solves; 0 solves the whole graph at once from the
  // initial estimates.
  int incremental_step = 50;
  // Max-Mixture only: a closure whose error at its first solve is within the
  // chi-square gate of its measurement noise plus the dead-reckoning drift of
  // its two poses (since their last kept closure) enters as a plain edge for
  // that solve, then as a Max-Mixture edge. Without it a true closure after a
  // long stretch without closures looks like an outlier and is never used.
  bool gate_new_closures = true;
  // Per solve.
  int max_iterations = 100;
  double function_tolerance = 1e-9;
};

// Empty when valid, else "null_weight must be in (0, 1]" and the like.
std::string ValidateSolveOptions(const SolveOptions& options);

struct SolveSummary {
  // Sum of e^T Omega e over the edges kept (all edges for kNone; for
  // kMaxMixture, every edge whose own component is chosen at the solution).
  double chi2 = 0.0;
  int iterations = 0;  // Levenberg-Marquardt steps, over all solves
  int solves = 0;
  double time_s = 0.0;
  int loop_closures = 0;
  int rejected = 0;                  // loop closures switched to the null
  std::vector<bool> pose_edge_kept;  // per graph.pose_edges entry
  bool converged = true;             // every solve reached a tolerance
};

// Solves in place: the graph's pose and point estimates become the solution.
// The graph's fixed vertices are held; with none, the first pose is. Throws
// std::invalid_argument for invalid options or an invalid graph
// (CheckPoseGraph). A vertex without edges keeps its estimate.
SolveSummary SolvePoseGraph(const SolveOptions& options, PoseGraph* graph);

}  // namespace parkslam::graph

#endif  // PARKSLAM_GRAPH_POSE_GRAPH_SOLVER_H_
