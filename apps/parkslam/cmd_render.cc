#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/map_json.h"
#include "parkslam/io/output_guard.h"
#include "parkslam/io/tum.h"
#include "parkslam/viz/map_svg.h"

namespace parkslam::app {

void AddRenderCommand(CLI::App& app) {
  struct Options {
    std::string map, out, title;
    std::vector<std::string> trajectories;
    double pixels_per_m = 10.0;
  };
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "render", "Draw a map (slots with their IDs, tags, obstacles) and trajectories as SVG");
  cmd->add_option("MAP", options->map, "Map JSON")->required();
  cmd->add_option("--out", options->out, "SVG file to write")->required();
  cmd->add_option("--trajectory", options->trajectories, "TUM trajectory to draw (repeatable)");
  cmd->add_option("--title", options->title, "Title above the picture");
  cmd->add_option("--pixels-per-m", options->pixels_per_m, "Scale")
      ->check(CLI::Range(1.0, 200.0))
      ->capture_default_str();
  cmd->callback([options] {
    std::vector<io::NamedPath> inputs{{options->map, "MAP"}};
    for (const std::string& t : options->trajectories) inputs.push_back({t, "--trajectory"});
    io::CheckOutputsSpareInputs({{options->out, "--out"}}, inputs);
    static const char* kColors[] = {"#2a9d2a", "#d62728", "#1f77b4",
                                    "#9467bd", "#ff7f0e", "#8c564b"};
    std::vector<viz::SvgTrajectory> trajectories;
    for (size_t i = 0; i < options->trajectories.size(); ++i) {
      trajectories.push_back({std::filesystem::path(options->trajectories[i]).filename().string(),
                              kColors[i % 6], io::ReadTum(options->trajectories[i])});
    }
    viz::MapSvgOptions svg_options;
    svg_options.pixels_per_m = options->pixels_per_m;
    svg_options.title = options->title.empty() ? options->map : options->title;
    io::WriteFileAtomically(
        options->out, viz::RenderMapSvg(io::ReadMap(options->map), trajectories, svg_options));
    std::printf("wrote %s\n", options->out.c_str());
  });
}

}  // namespace parkslam::app
