// parkslam update-map: a map of an earlier drive updated from a new drive of
// the same lot (mapping/map_update.h, docs/mapping.md "Updating a map").

#include <chrono>
#include <cstdio>
#include <optional>
#include <string>

#include "commands.h"
#include "parkslam/io/dataset.h"
#include "parkslam/io/map_json.h"
#include "parkslam/io/output_guard.h"
#include "parkslam/mapping/map_update.h"
#include "steps.h"

namespace parkslam::app {

namespace update_map_command {

struct Options {
  std::string map, dataset, out, label, drive_map_out;
  PixelOptions pixels;
  ConfigOptions config;
};

void Run(const Options& o) {
  io::CheckOutputsSpareInputs({{o.out, "--out"}, {o.drive_map_out, "--drive-map-out"}},
                              {{o.dataset, "DIR"}, {o.map, "--map"}});
  const AlgorithmOptions config = o.config.Load();
  const SemanticMap old_map = io::ReadMap(o.map);
  const io::Dataset dataset = io::ReadDataset(o.dataset);
  const auto start = std::chrono::steady_clock::now();
  mapping::Mapper mapper = BuildMap(dataset, config.mapper, std::nullopt, true,
                                    o.pixels.Stream(o.dataset, config.front_end), nullptr, {});
  const SemanticMap drive_map = mapper.Map();
  if (!o.drive_map_out.empty()) io::WriteMap(o.drive_map_out, drive_map);
  mapping::MapUpdateOptions options;
  options.label = o.label.empty() ? dataset.name : o.label;
  mapping::MapUpdateReport r;
  SemanticMap updated;
  try {
    updated = mapping::UpdateMap(old_map, drive_map, mapper.KeyframeTrajectory(), options, &r);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(o.dataset + " onto " + o.map + ": " + e.what());
  }
  const double total_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  io::WriteMap(o.out, updated);
  std::printf(
      "the drive's map (%zu slots, %zu tags) laid on the old one (%zu slots, %zu tags) by %d of "
      "%d landmarks named alike: x %.3f m, y %.3f m, yaw %.4f rad\n",
      drive_map.slots.size(), drive_map.tags.size(), old_map.slots.size(), old_map.tags.size(),
      r.alignment_inliers, r.alignment_pairs, r.T_old_new.x(), r.T_old_new.y(), r.T_old_new.yaw());
  std::printf(
      "slots: %d confirmed, %d moved, %d repainted, %d added, %d not seen (kept), %d sightings at "
      "odds with themselves or doubled (left out)\n",
      r.slots_confirmed, r.slots_moved, r.slots_repainted, r.slots_added, r.slots_unconfirmed,
      r.slots_disputed);
  std::printf("tags: %d confirmed, %d moved, %d added, %d removed, %d not seen (kept)\n",
              r.tags_confirmed, r.tags_moved, r.tags_added, r.tags_removed, r.tags_unconfirmed);
  std::printf("updated map (%zu slots, %zu tags, confirmed as '%s') written to %s in %.1f s\n",
              updated.slots.size(), updated.tags.size(), options.label.c_str(), o.out.c_str(),
              total_s);
}

}  // namespace update_map_command

void AddUpdateMapCommand(CLI::App& app) {
  using namespace update_map_command;
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "update-map",
      "Update a map from a new drive of the same lot: maps the drive, lays its map on the old "
      "one by the landmarks both name alike, keeps what still holds, moves what moved, renames "
      "repainted slots, adds what is new, removes tags the drive had in view and did not find, "
      "and stamps what it confirmed with --label");
  cmd->add_option("--map", options->map, "The map to update (JSON)")->required();
  cmd->add_option("DIR", options->dataset, "The new drive's dataset folder")->required();
  cmd->add_option("--out", options->out, "The updated map to write (JSON)")->required();
  cmd->add_option("--label", options->label,
                  "What every landmark the drive confirmed records as last_confirmed (default: "
                  "the dataset's name)");
  cmd->add_option("--drive-map-out", options->drive_map_out,
                  "Also write the new drive's own map (in its own frame)");
  AddPixelOptions(cmd, &options->pixels);
  AddConfigOptions(cmd, &options->config);
  cmd->callback([options] { Run(*options); });
}

}  // namespace parkslam::app
