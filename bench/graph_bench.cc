// The robust pose graph on synthetic benchmark graphs with known truth
// (issue: "the robust graph on the field's benchmarks"): a Manhattan world
// in the style of M3500 and a ring of laps, with random outlier loop closures
// and groups of mutually consistent wrong ones. Prints, per case, the
// trajectory RMSE of plain least squares and of Max-Mixture against the
// outlier-free solution, the chi-square over the kept edges, the closures
// rejected and the time.
//
//   parkslam_graph_bench [--seed 1] [--null-weight 0.01] [--null-scale 1e-11]
//                        [--step 50] [--no-gate] [--schedule auto|batch|incremental]
//                        [--no-calibration] [--quick] [--standard DIR]
//
// With --standard DIR (../shared/data/graphs), the field's standard graphs
// instead: M3500 and Intel, each against its outlier-free optimum (plain
// least squares on the clean file), with 1,000 random (for M3500 the
// standard file m3500_out1000_random.g2o), 1,000 local and 100 x 10
// grouped wrong closures (docs/pose_graph.md, "The standard sets").

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "parkslam/eval/trajectory_metrics.h"
#include "parkslam/graph/pose_graph_solver.h"
#include "parkslam/io/g2o.h"
#include "parkslam/sim/pose_graph_generator.h"

namespace parkslam {
namespace {

struct Outcome {
  double rmse_m = 0.0;
  graph::SolveSummary summary;
  int true_rejected = 0;   // closures of the clean graph switched off
  int false_accepted = 0;  // added outliers kept
};

Outcome Solve(const graph::SolveOptions& options, const sim::SyntheticGraph& problem,
              size_t clean_edges) {
  graph::PoseGraph g = problem.graph;
  Outcome out;
  out.summary = graph::SolvePoseGraph(options, &g);
  out.rmse_m = eval::AlignedPositionRmse(g.poses, problem.truth);
  for (size_t i = 0; i < g.pose_edges.size(); ++i) {
    if (graph::IsOdometry(g.pose_edges[i])) continue;
    if (i < clean_edges && !out.summary.pose_edge_kept[i]) ++out.true_rejected;
    if (i >= clean_edges && out.summary.pose_edge_kept[i]) ++out.false_accepted;
  }
  return out;
}

struct Case {
  std::string name;
  int random = 0;
  int groups = 0;
  int group_size = 0;
};

void Run(const std::string& world_name, const sim::SyntheticGraphOptions& world,
         const graph::SolveOptions& mixture, std::uint64_t seed, bool quick) {
  const sim::SyntheticGraph clean = sim::MakeSyntheticGraph(world, seed);
  const size_t clean_edges = clean.graph.pose_edges.size();
  graph::SolveOptions plain = mixture;
  plain.robust = graph::RobustKernel::kNone;
  const Outcome reference = Solve(plain, clean, clean_edges);
  const int closures = reference.summary.loop_closures;
  std::printf("\n%s: %zu poses, %d true loop closures; dead reckoning RMSE %.3f m\n",
              world_name.c_str(), clean.graph.poses.size(), closures,
              eval::AlignedPositionRmse(clean.graph.poses, clean.truth));
  std::printf("%-22s %8s %11s %11s %7s %10s %10s %9s %9s %7s\n", "outliers", "count", "plain m",
              "maxmix m", "ratio", "chi2 plain", "chi2 mm", "true off", "false on", "time s");
  std::vector<Case> cases = {{"none"},
                             {"random 10 %", closures / 10},
                             {"random 100", 100},
                             {"random 1000", 1000},
                             {"groups 10 x 10", 0, 10, 10},
                             {"groups 10 % (x 5)", 0, closures / 50, 5}};
  if (quick) cases.resize(2);
  for (const Case& c : cases) {
    sim::SyntheticGraph problem = clean;
    Random random(seed * 1000 + 7);
    int added = sim::AddRandomOutliers(c.random, &random, &problem.graph);
    added +=
        sim::AddGroupedOutliers(c.groups, c.group_size, problem.truth, &random, &problem.graph);
    const Outcome p = Solve(plain, problem, clean_edges);
    const Outcome m = Solve(mixture, problem, clean_edges);
    std::printf("%-22s %8d %11.4f %11.4f %7.3f %10.1f %10.1f %9d %9d %7.2f\n", c.name.c_str(),
                added, p.rmse_m, m.rmse_m, m.rmse_m / reference.rmse_m, p.summary.chi2,
                m.summary.chi2, m.true_rejected, m.false_accepted, m.summary.time_s);
  }
  std::printf("outlier-free plain solution: RMSE %.4f m, chi2 %.1f, %.2f s\n", reference.rmse_m,
              reference.summary.chi2, reference.summary.time_s);
}

// One standard graph: its optimum as the truth, then each outlier kind.
void RunStandard(const std::string& dir, const std::string& name,
                 const graph::SolveOptions& mixture, std::uint64_t seed) {
  sim::SyntheticGraph clean;
  clean.graph = io::ReadG2o(dir + "/" + name + ".g2o");
  graph::PoseGraph optimum = clean.graph;
  graph::SolveOptions plain = mixture;
  plain.robust = graph::RobustKernel::kNone;
  const graph::SolveSummary reference = graph::SolvePoseGraph(plain, &optimum);
  clean.truth = optimum.poses;
  const size_t clean_edges = clean.graph.pose_edges.size();
  std::printf("\n%s: %zu poses, %d loop closures; outlier-free optimum chi2 %.4f in %.2f s\n",
              name.c_str(), clean.graph.poses.size(), reference.loop_closures, reference.chi2,
              reference.time_s);
  std::printf("%-16s %8s %11s %11s %12s %9s %9s %6s %9s %7s\n", "outliers", "count", "plain m",
              "maxmix m", "chi2 mm", "true off", "false on", "scale", "schedule", "time s");
  const std::vector<Case> cases = {
      {"none"}, {"random 1000", 1000}, {"local 1000"}, {"groups 100 x 10", 0, 100, 10}};
  for (const Case& c : cases) {
    sim::SyntheticGraph problem = clean;
    Random random(seed * 1000 + 7);
    int added = 0;
    if (c.name == "random 1000" && name == "m3500") {
      problem.graph = io::ReadG2o(dir + "/m3500_out1000_random.g2o");
      added = static_cast<int>(problem.graph.pose_edges.size() - clean_edges);
    } else if (c.name == "local 1000") {
      added = sim::AddLocalOutliers(1000, 20, problem.truth, &random, &problem.graph);
    } else {
      added = sim::AddRandomOutliers(c.random, &random, &problem.graph);
      added +=
          sim::AddGroupedOutliers(c.groups, c.group_size, problem.truth, &random, &problem.graph);
    }
    const Outcome p = Solve(plain, problem, clean_edges);
    const Outcome m = Solve(mixture, problem, clean_edges);
    std::printf("%-16s %8d %11.4f %11.4f %12.4f %9d %9d %6.2f %9s %7.2f\n", c.name.c_str(), added,
                p.rmse_m, m.rmse_m, m.summary.chi2, m.true_rejected, m.false_accepted,
                m.summary.information_scale, m.summary.schedule.c_str(), m.summary.time_s);
  }
}

}  // namespace
}  // namespace parkslam

int main(int argc, char** argv) {
  using namespace parkslam;
  std::uint64_t seed = 1;
  bool quick = false;
  std::string standard;
  graph::SolveOptions mixture;
  mixture.robust = graph::RobustKernel::kMaxMixture;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--seed" && i + 1 < argc) {
      seed = std::strtoull(argv[++i], nullptr, 10);
    } else if (a == "--null-weight" && i + 1 < argc) {
      mixture.null_weight = std::atof(argv[++i]);
    } else if (a == "--null-scale" && i + 1 < argc) {
      mixture.null_information_scale = std::atof(argv[++i]);
    } else if (a == "--step" && i + 1 < argc) {
      mixture.incremental_step = std::atoi(argv[++i]);
    } else if (a == "--no-gate") {
      mixture.gate_new_closures = false;
    } else if (a == "--standard" && i + 1 < argc) {
      standard = argv[++i];
    } else if (a == "--no-calibration") {
      mixture.calibrate_information = false;
    } else if (a == "--schedule" && i + 1 < argc) {
      const std::string schedule = argv[++i];
      mixture.schedule = schedule == "batch"         ? graph::Schedule::kBatch
                         : schedule == "incremental" ? graph::Schedule::kIncremental
                                                     : graph::Schedule::kAuto;
    } else if (a == "--quick") {
      quick = true;
    } else {
      std::fprintf(stderr,
                   "usage: parkslam_graph_bench [--seed 1] [--null-weight 0.01] "
                   "[--null-scale 1e-11] [--step 50] [--no-gate] "
                   "[--schedule auto|batch|incremental] [--no-calibration] [--quick] "
                   "[--standard DIR]\n");
      return a == "--help" || a == "-h" ? 0 : 2;
    }
  }
  if (const std::string error = graph::ValidateSolveOptions(mixture); !error.empty()) {
    std::fprintf(stderr, "parkslam_graph_bench: %s\n", error.c_str());
    return 2;
  }
  std::printf(
      "Max-Mixture: null weight %g, information scale %g (switch above chi2 %.1f), "
      "incremental step %d, gate of new closures %s\n",
      mixture.null_weight, mixture.null_information_scale,
      2.0 * (-std::log(mixture.null_weight) - 1.5 * std::log(mixture.null_information_scale)) /
          (1.0 - mixture.null_information_scale),
      mixture.incremental_step, mixture.gate_new_closures ? "on" : "off");
  if (!standard.empty()) {
    try {
      RunStandard(standard, "m3500", mixture, seed);
      RunStandard(standard, "intel", mixture, seed);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "parkslam_graph_bench: %s\n", e.what());
      return 1;
    }
    return 0;
  }
  sim::SyntheticGraphOptions manhattan;
  Run("Manhattan world", manhattan, mixture, seed, quick);
  sim::SyntheticGraphOptions ring;
  ring.world = sim::GraphWorld::kRing;
  ring.poses = 2000;
  Run("Ring, 10 laps", ring, mixture, seed, quick);
  return 0;
}
