#ifndef PARKSLAM_GRAPH_POSE_GRAPH_SOLVER_H_
#define PARKSLAM_GRAPH_POSE_GRAPH_SOLVER_H_

// Least-squares solution of a planar pose graph, plain or with Max-Mixture
// loop closures (max_mixture_pose_edge_factor.h). Odometry edges (between
// consecutive ids) and pose-to-point edges are always trusted; every other
// pose edge is a loop closure and, with kMaxMixture, may be switched to its
// null hypothesis.
//
// Local minima. A Max-Mixture edge picks its component from the current
// estimate, so from dead reckoning that has drifted far every true closure
// looks like an outlier too. Two schedules meet that:
//  - batch: the whole graph solved at once from the initial estimates, with
//    a null so weak (information scale 1e-11) that its threshold is far out
//    (e^T Omega e = 85) and a trust region large enough that the first steps
//    are Gauss-Newton steps over the closures that fit. Where the initial
//    estimates are fair (Olson's M3500, Intel) it finds the optimum in a few
//    seconds; it is the field's usual set-up.
//  - incremental, as the mapper runs online: poses are added in id order,
//    `incremental_step` at a time; each new pose starts from its initial
//    estimate moved by the correction its predecessor received; a new closure
//    within the drift of its poses enters as a plain edge for one solve (the
//    gate). A closure is thus first judged against a trajectory corrected by
//    all earlier closures. Needed where dead reckoning drifts by metres (a
//    ring of laps), slow where the files' information is loose.
// kAuto runs both, the incremental one with the information already sized
// by the closures batch kept (calibration, below), and keeps the solution of
// lower Max-Mixture cost (MixtureCost) in that same model. A closure that
// disagrees with the odometry between its poses (chi2 against the odometry
// chain past chi-square(3)'s 0.999 quantile) is never let in through the
// gate: two poses a few steps apart may have drifted far together while
// their relative pose is well known.
//
// Calibration. The files' information matrices rarely match their noise:
// M3500's say sigma 0.15 where its closures fit to a few centimetres, so its
// wrong closures that happen to land within 0.15 m (chi2 below 85) are kept.
// With `calibrate_information`, once solved, every edge's information is
// scaled so that the kept closures fit chi-square(3), and the mixture is
// solved again from there, in rounds while the kept set changes: first by
// their median (robust while fewer than half of the kept ones are wrong: it
// sheds those a loose information let in), then by their mean (the
// a-posteriori variance factor of geodesy, which real closures' heavier
// tails, Intel's, widen). Where batch's kept closures say a noise far
// looser than the closures' agreement with odometry does (wrong closures
// within a file's loose information, which batch keeps), the incremental
// schedule runs at the odometry's scale instead, and at the end each kept
// closure that fits badly is tried at its null, kept there where the
// Max-Mixture cost falls (the local minima such closures bend the
// trajectory into; docs/pose_graph.md, "Judged against odometry first").
// The reported chi2 is the file's own.
#include <string>
#include <vector>

#include "parkslam/graph/pose_graph.h"

namespace parkslam::graph {

enum class RobustKernel { kNone, kMaxMixture };
enum class TrustRegion { kLevenbergMarquardt, kDogleg };
enum class Schedule { kAuto, kBatch, kIncremental };

struct SolveOptions {
  RobustKernel robust = RobustKernel::kNone;
  // The null hypothesis of a Max-Mixture closure: its weight against the
  // edge's 1 and the scale of its information. With the defaults a closure
  // is switched off above e^T Omega e = 85.2 (NullThresholdChi2).
  double null_weight = 1e-2;
  double null_information_scale = 1e-11;
  // Plain least squares is solved in one batch unless kIncremental (the
  // same optimum on M3500, Intel and the synthetic graphs, 10 to 35 times
  // faster than the incremental schedule).
  Schedule schedule = Schedule::kAuto;
  bool calibrate_information = true;  // Max-Mixture only
  // Poses added between solves of the incremental schedule; 0 solves the
  // whole graph at once from the initial estimates.
  int incremental_step = 50;
  // Max-Mixture only: a closure whose error at its first solve is within the
  // chi-square gate of its measurement noise plus the dead-reckoning drift of
  // its two poses (since their last kept closure) enters as a plain edge for
  // that solve, then as a Max-Mixture edge. Without it a true closure after a
  // long stretch without closures looks like an outlier and is never used.
  bool gate_new_closures = true;
  // Per solve. Ceres' trust region and its initial radius.
  TrustRegion trust_region = TrustRegion::kLevenbergMarquardt;
  double initial_trust_region_radius = 1e12;
  int max_iterations = 100;
  double function_tolerance = 1e-9;
  // Wall-clock budget of the whole solve, every schedule and round
  // together; 0: none. A solve that runs out stops where it is, with
  // SolveSummary::out_of_time (Max-Mixture on 20,000 poses ran past 10
  // minutes on two cores, where plain least squares takes 12 s).
  double time_budget_s = 0.0;
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
  // A solve whose linear solver failed (a factorization refused, the
  // problem too large or degenerate): the estimates are not a solution.
  bool failed = false;
  // The time budget ran out before the last solve ended: the estimates are
  // not a solution either.
  bool out_of_time = false;
  // Max-Mixture: the schedule whose solution was kept ("batch",
  // "incremental"), and the factor calibration put on every information
  // matrix (1 without calibration).
  std::string schedule;
  double information_scale = 1.0;
};

// The Max-Mixture negative log-likelihood (up to a constant) at the graph's
// estimates: 0.5 e^T Omega e for odometry and point edges, and for each
// closure the smaller of its own component's 0.5 e^T Omega e and the null's
// -log w - 1.5 log s + 0.5 s e^T Omega e. With kNone, half the chi2.
double MixtureCost(const SolveOptions& options, const PoseGraph& graph);

// Solves in place: the graph's pose and point estimates become the solution.
// The graph's fixed vertices are held; with none, the first pose is. Throws
// std::invalid_argument for invalid options or an invalid graph
// (CheckPoseGraph). A vertex without edges keeps its estimate.
SolveSummary SolvePoseGraph(const SolveOptions& options, PoseGraph* graph);

}  // namespace parkslam::graph

#endif  // PARKSLAM_GRAPH_POSE_GRAPH_SOLVER_H_
