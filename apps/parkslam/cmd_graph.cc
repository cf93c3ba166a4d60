// parkslam solve-graph and make-graph: the robust pose graph on its own, on
// standard 2D g2o files (docs/pose_graph.md).

#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "commands.h"
#include "parkslam/eval/trajectory_metrics.h"
#include "parkslam/graph/max_mixture_pose_edge_factor.h"
#include "parkslam/graph/pose_graph_solver.h"
#include "parkslam/io/g2o.h"
#include "parkslam/io/output_guard.h"
#include "parkslam/sim/pose_graph_generator.h"

namespace parkslam::app {

void AddSolveGraphCommand(CLI::App& app) {
  struct Options {
    std::string in, out, truth;
    std::string robust = "none";
    graph::SolveOptions solve;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
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
                  "Weight of the null hypothesis against the closure's 1")
      ->check(CLI::Range(1e-12, 1.0))
      ->capture_default_str();
  cmd->add_option("--null-scale", options->solve.null_information_scale,
                  "Information of the null hypothesis as a fraction of the closure's")
      ->check(CLI::Range(1e-15, 0.999))
      ->capture_default_str();
  cmd->add_option("--step", options->solve.incremental_step,
                  "Poses added between solves (0: one batch solve from the file's estimates)")
      ->check(CLI::Range(0, 100000000))
      ->capture_default_str();
  cmd->add_option("--max-iterations", options->solve.max_iterations, "Per solve")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  cmd->add_option("--truth", options->truth,
                  "A .g2o graph of the true poses: report the aligned position RMSE");
  cmd->add_flag("--json", options->json, "Print one JSON object");
  cmd->callback([options] {
    std::vector<io::NamedPath> inputs = {{options->in, "FILE"}};
    if (!options->truth.empty()) inputs.push_back({options->truth, "--truth"});
    io::CheckOutputsSpareInputs({{options->out, "--out"}}, inputs);
    graph::PoseGraph g = io::ReadG2o(options->in);
    graph::PoseGraph truth;
    if (!options->truth.empty()) truth = io::ReadG2o(options->truth);
    options->solve.robust =
        options->robust == "maxmix" ? graph::RobustKernel::kMaxMixture : graph::RobustKernel::kNone;
    const graph::SolveSummary s = graph::SolvePoseGraph(options->solve, &g);
    io::WriteG2o(options->out, g);
    nlohmann::json j = {{"chi2", s.chi2},          {"iterations", s.iterations},
                        {"time_s", s.time_s},      {"loop_closures", s.loop_closures},
                        {"rejected", s.rejected},  {"solves", s.solves},
                        {"converged", s.converged}};
    if (!options->truth.empty()) j["rmse_m"] = eval::AlignedPositionRmse(g.poses, truth.poses);
    if (options->json) {
      std::printf("%s\n", j.dump().c_str());
      return;
    }
    std::printf("%zu poses, %zu points, %zu pose edges (%d loop closures), %zu point edges\n",
                g.poses.size(), g.points.size(), g.pose_edges.size(), s.loop_closures,
                g.point_edges.size());
    if (options->solve.robust == graph::RobustKernel::kMaxMixture) {
      std::printf("Max-Mixture: %d of %d loop closures rejected (null above chi2 %.1f)\n",
                  s.rejected, s.loop_closures,
                  graph::MaxMixturePoseEdgeFactor::NullThresholdChi2(
                      options->solve.null_weight, options->solve.null_information_scale));
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

void AddMakeGraphCommand(CLI::App& app) {
  struct Options {
    std::string out, truth;
    std::string world = "manhattan";
    sim::SyntheticGraphOptions graph;
    int random_outliers = 0;
    int groups = 0;
    int group_size = 10;
    std::uint64_t seed = 1;
  };
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "make-graph",
      "Write a synthetic 2D pose graph with known truth in g2o format: a Manhattan world "
      "(1 m steps on a grid, in the style of M3500) or a ring of laps, with optional outlier "
      "loop closures, random or in mutually consistent groups");
  cmd->add_option("--out", options->out, "Output .g2o graph (dead-reckoning estimates)")
      ->required();
  cmd->add_option("--truth", options->truth, "Also write the true poses as a .g2o graph");
  cmd->add_option("--world", options->world, "manhattan or ring")
      ->check(CLI::IsMember({"manhattan", "ring"}))
      ->capture_default_str();
  cmd->add_option("--poses", options->graph.poses, "Number of poses")
      ->check(CLI::Range(2, 1000000))
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
  cmd->add_option("--groups", options->groups, "Groups of mutually consistent wrong loop closures")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  cmd->add_option("--group-size", options->group_size, "Closures per group")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  cmd->add_option("--seed", options->seed, "Random seed")->capture_default_str();
  cmd->callback([options] {
    if (!options->truth.empty()) {
      io::CheckOutputsSpareInputs({{options->out, "--out"}}, {{options->truth, "--truth"}});
    }
    options->graph.world =
        options->world == "ring" ? sim::GraphWorld::kRing : sim::GraphWorld::kManhattan;
    sim::SyntheticGraph made = sim::MakeSyntheticGraph(options->graph, options->seed);
    Random random = Random::Derive(options->seed, 0x6f75746c69657273ULL);
    const int random_added = sim::AddRandomOutliers(options->random_outliers, &random, &made.graph);
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
        "%zu poses, %d loop closures of which %d random and %d grouped outliers; wrote %s\n",
        made.graph.poses.size(), closures, random_added, grouped, options->out.c_str());
  });
}

}  // namespace parkslam::app
