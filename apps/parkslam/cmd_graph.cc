// parkslam solve-graph and make-graph: the robust pose graph on its own, on
// standard 2D g2o files (docs/pose_graph.md).

#include <algorithm>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.h"
#include "parkslam/common/field_checker.h"
#include "parkslam/eval/trajectory_metrics.h"
#include "parkslam/graph/max_mixture_pose_edge_factor.h"
#include "parkslam/graph/pose_graph_solver.h"
#include "parkslam/io/g2o.h"
#include "parkslam/io/output_guard.h"
#include "parkslam/sim/pose_graph_generator.h"

namespace parkslam::app {
namespace {

struct ClosureCounts {
  int true_off = 0;  // true closures switched off
  int false_on = 0;  // wrong closures kept
};

// With the last `wrong_last` loop closures of the graph known to be wrong.
ClosureCounts CountWrongLast(const graph::PoseGraph& g, const std::vector<bool>& kept,
                             int wrong_last) {
  int closures = 0;
  for (const graph::PoseEdge& e : g.pose_edges) closures += graph::IsOdometry(e) ? 0 : 1;
  if (wrong_last > closures) {
    throw std::invalid_argument("--wrong-last " + std::to_string(wrong_last) + " exceeds the " +
                                std::to_string(closures) + " loop closures of the graph");
  }
  ClosureCounts counts;
  int index = 0;
  for (size_t i = 0; i < g.pose_edges.size(); ++i) {
    if (graph::IsOdometry(g.pose_edges[i])) continue;
    const bool wrong = index++ >= closures - wrong_last;
    if (wrong && kept[i]) ++counts.false_on;
    if (!wrong && !kept[i]) ++counts.true_off;
  }
  return counts;
}

}  // namespace

void AddSolveGraphCommand(CLI::App& app) {
  struct Options {
    std::string in, out, truth;
    std::string robust = "none";
    std::string trust_region = "lm";
    std::string gate = "on";
    std::string schedule = "auto";
    std::string calibrate = "on";
    int wrong_last = 0;
    graph::SolveOptions solve;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  // Ten minutes: 20,000 poses of plain least squares take 12 s here, of
  // Max-Mixture over 10 minutes (docs/plausible_ranges.md, "Input sizes").
  options->solve.time_budget_s = 600.0;
  CLI::App* cmd = app.add_subcommand(
      "solve-graph",
      "Optimize a 2D pose graph in g2o format (VERTEX_SE2, EDGE_SE2, VERTEX_XY, EDGE_SE2_XY, "
      "FIX). Edges between consecutive ids are odometry; every other pose edge is a loop "
      "closure, which --robust maxmix may switch to a null hypothesis. Writes the graph with "
      "its optimized vertices");
  cmd->add_option("FILE", options->in, "Input .g2o graph")->required();
  cmd->add_option("--out", options->out, "Output .g2o graph")->required();
  cmd->add_option("--robust", options->robust,
                  "Loop closures: none (plain least squares) or "
                  "maxmix (Max-Mixture with a null hypothesis)")
      ->check(CLI::IsMember({"none", "maxmix"}))
      ->capture_default_str();
  cmd->add_option("--null-weight", options->solve.null_weight,
                  "Weight of the null hypothesis against the closure's 1 (default: the file's, "
                  "where it has EDGE_SE2_MIXTURE closures)")
      ->check(CLI::Range(1e-12, 1.0))
      ->capture_default_str();
  cmd->add_option("--null-scale", options->solve.null_information_scale,
                  "Information of the null hypothesis as a fraction of the closure's (default: "
                  "the file's, where it has EDGE_SE2_MIXTURE closures)")
      ->check(CLI::Range(1e-15, 0.999))
      ->capture_default_str();
  cmd->add_option("--step", options->solve.incremental_step,
                  "Poses added between solves of the incremental schedule (0: one batch solve)")
      ->check(CLI::Range(0, 100000000))
      ->capture_default_str();
  cmd->add_option("--schedule", options->schedule,
                  "batch (one solve from the file's estimates), incremental (--step poses at a "
                  "time, with --gate), or auto (plain: batch; Max-Mixture: both, the incremental "
                  "one with the information sized by batch's kept closures, and the lower "
                  "Max-Mixture cost kept)")
      ->check(CLI::IsMember({"auto", "batch", "incremental"}))
      ->capture_default_str();
  cmd->add_option("--calibrate", options->calibrate,
                  "Max-Mixture: scale the information so that the kept closures fit "
                  "chi-square(3) (by their median, then their mean) and solve again (on), or "
                  "trust the file's information (off)")
      ->check(CLI::IsMember({"on", "off"}))
      ->capture_default_str();
  cmd->add_option("--wrong-last", options->wrong_last,
                  "The last K loop closures of FILE are known to be wrong (as make-graph and the "
                  "standard outlier sets append them): report true closures rejected and wrong "
                  "ones kept")
      ->check(CLI::Range(0, 100000000));
  cmd->add_option("--gate", options->gate,
                  "Max-Mixture: new closures within the dead-reckoning drift enter as plain edges "
                  "for their first solve (on) or as mixtures at once (off)")
      ->check(CLI::IsMember({"on", "off"}))
      ->capture_default_str();
  cmd->add_option("--trust-region", options->trust_region,
                  "Ceres trust region: lm (Levenberg-Marquardt) or dogleg")
      ->check(CLI::IsMember({"lm", "dogleg"}))
      ->capture_default_str();
  cmd->add_option("--initial-radius", options->solve.initial_trust_region_radius,
                  "Initial trust-region radius")
      ->check(CLI::Range(1e-6, 1e16))
      ->capture_default_str();
  cmd->add_option("--max-iterations", options->solve.max_iterations, "Per solve")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  cmd->add_option("--time-budget-s", options->solve.time_budget_s,
                  "Wall-clock limit of the whole solve; past it nothing is written and the "
                  "command fails (0: none)")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  cmd->add_option("--truth", options->truth,
                  "A .g2o graph of the true poses: report the aligned position RMSE");
  cmd->add_flag("--json", options->json, "Print one JSON object");
  cmd->callback([options, cmd] {
    std::vector<io::NamedPath> inputs = {{options->in, "FILE"}};
    if (!options->truth.empty()) inputs.push_back({options->truth, "--truth"});
    io::CheckOutputsSpareInputs({{options->out, "--out"}}, inputs);
    graph::PoseGraph g = io::ReadG2o(options->in);
    graph::PoseGraph truth;
    if (!options->truth.empty()) truth = io::ReadG2o(options->truth);
    options->solve.robust =
        options->robust == "maxmix" ? graph::RobustKernel::kMaxMixture : graph::RobustKernel::kNone;
    // A file's own null (EDGE_SE2_MIXTURE) unless the command line names one.
    if (g.file_null && cmd->count("--null-weight") == 0) {
      options->solve.null_weight = g.file_null->weight;
    }
    if (g.file_null && cmd->count("--null-scale") == 0) {
      options->solve.null_information_scale = g.file_null->information_scale;
    }
    options->solve.gate_new_closures = options->gate == "on";
    options->solve.calibrate_information = options->calibrate == "on";
    options->solve.schedule = options->schedule == "batch"         ? graph::Schedule::kBatch
                              : options->schedule == "incremental" ? graph::Schedule::kIncremental
                                                                   : graph::Schedule::kAuto;
    options->solve.trust_region = options->trust_region == "dogleg"
                                      ? graph::TrustRegion::kDogleg
                                      : graph::TrustRegion::kLevenbergMarquardt;
    const graph::SolveSummary s = graph::SolvePoseGraph(options->solve, &g);
    if (s.out_of_time) {
      throw std::runtime_error(
          options->in + ": the solve ran past its time budget (--time-budget-s " +
          Limit(options->solve.time_budget_s) + " s" +
          ") before it ended; --out not written (a larger budget, or a smaller graph)");
    }
    if (s.failed) {
      throw std::runtime_error(options->in +
                               ": the solver failed (its linear solver could not factor the "
                               "problem: too large, or a part of it not constrained); --out "
                               "not written");
    }
    io::WriteG2o(options->out, g);
    nlohmann::json j = {{"chi2", s.chi2},          {"iterations", s.iterations},
                        {"time_s", s.time_s},      {"loop_closures", s.loop_closures},
                        {"rejected", s.rejected},  {"solves", s.solves},
                        {"converged", s.converged}};
    if (!options->truth.empty()) j["rmse_m"] = eval::AlignedPositionRmse(g.poses, truth.poses);
    if (options->solve.robust == graph::RobustKernel::kMaxMixture) {
      j["schedule"] = s.schedule;
      j["information_scale"] = s.information_scale;
    }
    if (options->wrong_last > 0) {
      const ClosureCounts c = CountWrongLast(g, s.pose_edge_kept, options->wrong_last);
      j["true_off"] = c.true_off;
      j["false_on"] = c.false_on;
    }
    if (options->json) {
      std::printf("%s\n", j.dump().c_str());
      return;
    }
    std::printf("%zu poses, %zu points, %zu pose edges (%d loop closures), %zu point edges\n",
                g.poses.size(), g.points.size(), g.pose_edges.size(), s.loop_closures,
                g.point_edges.size());
    if (options->solve.robust == graph::RobustKernel::kMaxMixture) {
      std::printf(
          "Max-Mixture: %d of %d loop closures rejected (null weight %.3g, information scale "
          "%.3g%s: above chi2 %.1f), %s schedule, information scaled by %.4g\n",
          s.rejected, s.loop_closures, options->solve.null_weight,
          options->solve.null_information_scale, g.file_null ? ", the file's" : "",
          graph::MaxMixturePoseEdgeFactor::NullThresholdChi2(options->solve.null_weight,
                                                             options->solve.null_information_scale),
          s.schedule.c_str(), s.information_scale);
    }
    if (j.contains("true_off")) {
      std::printf("of the last %d closures (wrong): %d kept; true closures rejected: %d\n",
                  options->wrong_last, j["false_on"].get<int>(), j["true_off"].get<int>());
    }
    std::printf("chi2 %.3f over the kept edges; %d iterations in %d solves, %.3f s%s\n", s.chi2,
                s.iterations, s.solves, s.time_s,
                s.converged ? "" : " (a solve stopped at its iteration limit)");
    if (j.contains("rmse_m")) {
      std::printf("position RMSE against --truth %.4f m\n", j["rmse_m"].get<double>());
    }
    std::printf("wrote %s\n", options->out.c_str());
  });
}

namespace {

struct MakeGraphOptions {
  std::string out, truth, base, base_truth;
  std::string world = "manhattan";
  sim::SyntheticGraphOptions graph;
  int random_outliers = 0;
  int local_outliers = 0;
  int local_window = 20;
  int groups = 0;
  int group_size = 10;
  std::uint64_t seed = 1;
};

// The graph to spoil: --base (with --base-truth, or its own estimates as the
// truth when only random outliers are asked for), else a synthetic one.
sim::SyntheticGraph MadeOrBaseGraph(const MakeGraphOptions& options) {
  if (options.base.empty()) {
    if (!options.base_truth.empty()) throw std::invalid_argument("--base-truth needs --base");
    sim::SyntheticGraphOptions graph = options.graph;
    graph.world = options.world == "ring" ? sim::GraphWorld::kRing : sim::GraphWorld::kManhattan;
    return sim::MakeSyntheticGraph(graph, options.seed);
  }
  sim::SyntheticGraph made;
  made.graph = io::ReadG2o(options.base);
  const int n = static_cast<int>(made.graph.poses.size());
  if (n < 3 || made.graph.poses.begin()->first != 0 || made.graph.poses.rbegin()->first != n - 1) {
    throw std::invalid_argument("--base " + options.base + ": its pose ids must be 0.." +
                                std::to_string(n - 1));
  }
  if (options.base_truth.empty()) {
    if (options.local_outliers > 0 || options.groups > 0) {
      throw std::invalid_argument("--local and --groups need --base-truth (the true poses of " +
                                  options.base + ")");
    }
    made.truth = made.graph.poses;
    return made;
  }
  made.truth = io::ReadG2o(options.base_truth).poses;
  if (made.truth.size() != made.graph.poses.size() ||
      !std::equal(made.truth.begin(), made.truth.end(), made.graph.poses.begin(),
                  [](const auto& a, const auto& b) { return a.first == b.first; })) {
    throw std::invalid_argument("--base-truth " + options.base_truth +
                                ": its pose ids differ from those of --base " + options.base);
  }
  return made;
}

}  // namespace

void AddMakeGraphCommand(CLI::App& app) {
  using Options = MakeGraphOptions;
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "make-graph",
      "Write a synthetic 2D pose graph with known truth in g2o format: a Manhattan world "
      "(1 m steps on a grid, in the style of M3500) or a ring of laps, with optional outlier "
      "loop closures, random, local or in mutually consistent groups. With --base, the "
      "outliers spoil a graph from a file instead (M3500, Intel)");
  cmd->add_option("--out", options->out, "Output .g2o graph (dead-reckoning estimates)")
      ->required();
  cmd->add_option("--truth", options->truth, "Also write the true poses as a .g2o graph");
  cmd->add_option("--world", options->world, "manhattan or ring")
      ->check(CLI::IsMember({"manhattan", "ring"}))
      ->capture_default_str();
  cmd->add_option("--poses", options->graph.poses,
                  "Number of poses (at most what solve-graph reads)")
      ->check(CLI::Range(2, static_cast<int>(io::kMaxG2oPoses)))
      ->capture_default_str();
  cmd->add_option("--sigma-xy", options->graph.sigma_xy_m, "Measurement noise, m")
      ->check(CLI::Range(1e-6, 9.9))
      ->capture_default_str();
  cmd->add_option("--sigma-yaw", options->graph.sigma_yaw_rad, "Measurement noise, rad")
      ->check(CLI::Range(1e-6, 0.99))
      ->capture_default_str();
  cmd->add_option("--closure-probability", options->graph.closure_probability,
                  "Chance of a true loop closure at a revisited place")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--outliers", options->random_outliers, "Random wrong loop closures")
      ->check(CLI::Range(0, 10000000))
      ->capture_default_str();
  cmd->add_option("--local", options->local_outliers,
                  "Local wrong loop closures: to a pose 2 to --local-window ids later, 0.5-2 m "
                  "and up to 0.5 rad off the true relative pose")
      ->check(CLI::Range(0, 10000000))
      ->capture_default_str();
  cmd->add_option("--local-window", options->local_window, "Ids between a local outlier's poses")
      ->check(CLI::Range(2, 100000))
      ->capture_default_str();
  cmd->add_option("--base", options->base,
                  "Spoil this .g2o graph (ids 0..n-1) instead of making one; --world, --poses and "
                  "the noise options are then unused");
  cmd->add_option("--base-truth", options->base_truth,
                  "With --base: its true poses (for an outlier-free real graph, its optimum), "
                  "which --local and --groups need");
  cmd->add_option("--groups", options->groups, "Groups of mutually consistent wrong loop closures")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  cmd->add_option("--group-size", options->group_size, "Closures per group")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  cmd->add_option("--seed", options->seed, "Random seed")->capture_default_str();
  cmd->callback([options] {
    std::vector<io::NamedPath> inputs;
    if (!options->base.empty()) inputs.push_back({options->base, "--base"});
    if (!options->base_truth.empty()) inputs.push_back({options->base_truth, "--base-truth"});
    std::vector<io::NamedPath> outputs = {{options->out, "--out"}};
    if (!options->truth.empty()) outputs.push_back({options->truth, "--truth"});
    io::CheckOutputsSpareInputs(outputs, inputs);
    sim::SyntheticGraph made = MadeOrBaseGraph(*options);
    // A graph solve-graph would refuse is not written at all.
    const double edges = static_cast<double>(made.graph.pose_edges.size()) +
                         options->random_outliers + options->local_outliers +
                         static_cast<double>(options->groups) * options->group_size;
    if (edges > static_cast<double>(io::kMaxG2oEdges)) {
      std::string message = "--outliers, --local and --groups x --group-size would give the graph ";
      message.append(std::to_string(static_cast<long long>(edges)))
          .append(" edges; solve-graph takes at most ")
          .append(std::to_string(io::kMaxG2oEdges))
          .append(" (docs/plausible_ranges.md, \"Input sizes\")");
      throw std::invalid_argument(message);
    }
    Random random = Random::Derive(options->seed, 0x6f75746c69657273ULL);
    const int random_added = sim::AddRandomOutliers(options->random_outliers, &random, &made.graph);
    const int local_added = sim::AddLocalOutliers(options->local_outliers, options->local_window,
                                                  made.truth, &random, &made.graph);
    const int grouped = sim::AddGroupedOutliers(options->groups, options->group_size, made.truth,
                                                &random, &made.graph);
    io::WriteG2o(options->out, made.graph);
    if (!options->truth.empty()) {
      graph::PoseGraph truth = made.graph;
      truth.poses = made.truth;
      io::WriteG2o(options->truth, truth);
    }
    int closures = 0;
    for (const graph::PoseEdge& e : made.graph.pose_edges) closures += graph::IsOdometry(e) ? 0 : 1;
    std::printf(
        "%zu poses, %d loop closures of which %d random, %d local and %d grouped outliers; "
        "wrote %s\n",
        made.graph.poses.size(), closures, random_added, local_added, grouped,
        options->out.c_str());
  });
}

}  // namespace parkslam::app
