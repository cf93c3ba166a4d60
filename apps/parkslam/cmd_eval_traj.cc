#include <cmath>
#include <cstdio>
#include <iostream>

#include "commands.h"
#include "parkslam/io/tum.h"
#include "steps.h"

namespace parkslam::app {

void AddEvalTrajCommand(CLI::App& app) {
  struct Options {
    std::string truth, estimate;
    bool json = false;
    bool no_align = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "eval-traj",
      "Compare an estimated trajectory with the truth: ATE after SE(2) alignment, RPE per "
      "10 m, drift per 100 m, length");
  cmd->add_option("--truth", options->truth, "Ground-truth TUM trajectory")->required();
  cmd->add_option("--estimate", options->estimate, "Estimated TUM trajectory")->required();
  cmd->add_flag("--json", options->json, "Print one JSON object");
  cmd->add_flag("--no-align", options->no_align,
                "Compare in the given frames, without SE(2) alignment");
  cmd->callback([options] {
    const Trajectory truth = io::ReadTum(options->truth);
    const Trajectory estimate = io::ReadTum(options->estimate);
    eval::TrajectoryMetricsOptions metrics_options;
    metrics_options.align = !options->no_align;
    const eval::TrajectoryMetrics m = eval::EvaluateTrajectory(truth, estimate, metrics_options);
    if (options->json) {
      std::cout << MetricsToJson(m).dump() << "\n";
      return;
    }
    std::printf("poses matched        %d\n", m.matched_poses);
    std::printf("length               %.2f m\n", m.length_m);
    std::printf("ATE rmse / mean / max %.3f / %.3f / %.3f m\n", m.ate_rmse_m, m.ate_mean_m,
                m.ate_max_m);
    std::printf("yaw rmse / max       %.3f / %.3f deg\n", m.yaw_rmse_rad * 180 / M_PI,
                m.yaw_max_rad * 180 / M_PI);
    std::printf("RPE per 10 m         %.3f m, %.3f deg (rmse)\n", m.rpe_trans_rmse_m,
                m.rpe_yaw_rmse_rad * 180 / M_PI);
    if (std::isfinite(m.drift_per_100m_m)) {
      std::printf("drift per 100 m      %.3f m (%.2f %%)\n", m.drift_per_100m_m, m.drift_percent);
    } else {
      std::printf("drift per 100 m      n/a (path shorter than 100 m)\n");
    }
  });
}

}  // namespace parkslam::app
