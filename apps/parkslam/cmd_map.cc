#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.h"
#include "parkslam/eval/map_metrics.h"
#include "parkslam/harness/dead_reckoning.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/dataset.h"
#include "parkslam/io/map_json.h"
#include "parkslam/io/output_guard.h"
#include "parkslam/io/tum.h"
#include "progress.h"
#include "steps.h"

namespace parkslam::app {

namespace map_command {

struct Options {
  std::string dataset, out, trajectory_out, robust = "maxmix", mode = "batch", init, solver = "lm";
  double initial_trust_region = 1e8;
  std::string track_out;
  double track_every_s = 10.0;
  bool track_batch = false;
  PixelOptions pixels;
  ConfigOptions config;
};

// The mapper's options from --config with the command's choices over them;
// the initial trust region only where given.
mapping::MapperOptions MapperOptionsOf(const Options& o, const AlgorithmOptions& config,
                                       bool initial_trust_region_given) {
  mapping::MapperOptions mapper_options = config.mapper;
  mapper_options.robust =
      o.robust == "none" ? mapping::RobustMode::kNone : mapping::RobustMode::kMaxMixture;
  mapper_options.mode =
      o.mode == "online" ? mapping::MappingMode::kOnline : mapping::MappingMode::kBatch;
  mapper_options.trust_region = o.solver == "dogleg" ? mapping::TrustRegion::kDogleg
                                                     : mapping::TrustRegion::kLevenbergMarquardt;
  if (initial_trust_region_given) {
    mapper_options.initial_trust_region_radius = o.initial_trust_region;
  }
  return mapper_options;
}

// The map as it stands along the drive (Mapper::Map with the slots seen
// twice), scored against the dataset's truth every track_every_s of drive:
// what a car mapping live has at each moment (docs/mapping.md, "Online at
// batch accuracy").
class Track {
 public:
  Track(const io::Dataset& dataset, double every_s, bool batch)
      : every_ns_(FromSeconds(every_s)), batch_(batch) {
    if (!dataset.groundtruth_map) {
      throw std::runtime_error("--track-out: the dataset has no ground-truth map to score against");
    }
    truth_ = *dataset.groundtruth_map;
    // When each truth slot was passed a second time: its first sighting
    // that follows the one before by more than kPassGap_s (the labels are
    // per slot frame of the log). No labels: none is known revisited.
    revisited_ns_.assign(truth_.slots.size(), std::numeric_limits<TimeNs>::max());
    std::vector<TimeNs> last_ns(truth_.slots.size(), -1);
    const auto& frames = dataset.log.slot_frames;
    for (size_t f = 0; f < dataset.slot_labels.size() && f < frames.size(); ++f) {
      for (const int label : dataset.slot_labels[f]) {
        if (label < 0 || static_cast<size_t>(label) >= truth_.slots.size()) continue;
        const TimeNs t_ns = frames[f].t_ns;
        TimeNs& last = last_ns[static_cast<size_t>(label)];
        TimeNs& revisited = revisited_ns_[static_cast<size_t>(label)];
        if (last >= 0 && ToSeconds(t_ns - last) > kPassGap_s) revisited = std::min(revisited, t_ns);
        last = t_ns;
      }
    }
  }

  void Watch(const mapping::Mapper& mapper, TimeNs t_ns) {
    if (mapper.keyframes().empty()) return;
    if (next_ns_ < 0) next_ns_ = t_ns + every_ns_;
    if (t_ns < next_ns_) return;
    next_ns_ += every_ns_ * ((t_ns - next_ns_) / every_ns_ + 1);
    const SemanticMap map = mapper.Map(2);
    Row row{ToSeconds(t_ns), eval::EvaluateMap(map, truth_), {}, {}, {}};
    eval::MapMetricsOptions revisited;
    revisited.truth_slot_mask.resize(truth_.slots.size());
    for (size_t i = 0; i < truth_.slots.size(); ++i) {
      revisited.truth_slot_mask[i] = revisited_ns_[i] <= t_ns;
    }
    row.revisited = eval::EvaluateMap(map, truth_, revisited);
    if (batch_) {
      const SemanticMap batch = mapper.BatchMapSoFar(2);
      row.batch = eval::EvaluateMap(batch, truth_);
      row.batch_revisited = eval::EvaluateMap(batch, truth_, revisited);
    }
    rows_.push_back(row);
  }

  // t_s; the slots seen twice: matched, their observed corners' count,
  // RMSE and max; the same of the slots passed twice; tags: matched, RMSE;
  // with --track-batch the RMSEs of the batch map so far.
  void Write(const std::string& path) const {
    std::string csv =
        "t_s,slots_matched,observed_corners,observed_rmse_m,observed_max_m,revisited_slots,"
        "revisited_rmse_m,revisited_max_m,tags_matched,tag_rmse_m";
    if (batch_) csv += ",batch_observed_rmse_m,batch_revisited_rmse_m,batch_tag_rmse_m";
    csv += "\n";
    char line[256];
    for (const Row& row : rows_) {
      const eval::MapMetrics& m = row.metrics;
      const eval::MapMetrics& r = row.revisited;
      std::snprintf(line, sizeof line, "%.3f,%d,%d,%.4f,%.4f,%d,%.4f,%.4f,%d,%.4f", row.t_s,
                    m.slots_matched, m.observed_corners.count, m.observed_corners.rmse_m,
                    m.observed_corners.max_m, r.slots_matched, r.observed_corners.rmse_m,
                    r.observed_corners.max_m, m.tags_matched, m.tag_rmse_m);
      csv += line;
      if (batch_) {
        std::snprintf(line, sizeof line, ",%.4f,%.4f,%.4f", row.batch.observed_corners.rmse_m,
                      row.batch_revisited.observed_corners.rmse_m, row.batch.tag_rmse_m);
        csv += line;
      }
      csv += "\n";
    }
    io::WriteFileAtomically(path, csv);
  }

  std::string Describe() const {
    std::string text = "along the drive (" + std::to_string(rows_.size()) + " moments)";
    text += Worst("slots seen twice", &Row::metrics, &Row::batch);
    text += Worst("slots passed twice", &Row::revisited, &Row::batch_revisited);
    return text;
  }

 private:
  struct Row;
  // The worst moment of one kind of slot: its observed corners' RMSE, and
  // with --track-batch the batch map's worst and the largest ratio of the
  // two at one moment.
  std::string Worst(const char* what, eval::MapMetrics Row::*online,
                    eval::MapMetrics Row::*batch) const {
    double worst = -1.0, worst_t_s = 0.0, worst_batch = 0.0, worst_ratio = 0.0;
    for (const Row& row : rows_) {
      const eval::CornerErrors& e = (row.*online).observed_corners;
      if (e.count == 0) continue;
      if (e.rmse_m > worst) {
        worst = e.rmse_m;
        worst_t_s = row.t_s;
      }
      const eval::CornerErrors& b = (row.*batch).observed_corners;
      if (batch_ && b.count > 0) {
        worst_batch = std::max(worst_batch, b.rmse_m);
        worst_ratio = std::max(worst_ratio, e.rmse_m / std::max(b.rmse_m, 1e-9));
      }
    }
    char text[256];
    if (worst < 0.0) {
      std::snprintf(text, sizeof text, "; %s: none", what);
    } else if (!batch_) {
      std::snprintf(text, sizeof text, "; %s: observed corners at worst %.3f m RMSE (%.0f s)", what,
                    worst, worst_t_s);
    } else {
      std::snprintf(text, sizeof text,
                    "; %s: observed corners at worst %.3f m RMSE (%.0f s), batch so far at "
                    "worst %.3f m, online over batch at most %.2f",
                    what, worst, worst_t_s, worst_batch, worst_ratio);
    }
    return text;
  }

  struct Row {
    double t_s;
    eval::MapMetrics metrics;
    // Only the slots passed twice by then (kPassGap_s apart).
    eval::MapMetrics revisited;
    eval::MapMetrics batch, batch_revisited;  // with --track-batch
  };
  static constexpr double kPassGap_s = 20.0;
  std::vector<TimeNs> revisited_ns_;
  SemanticMap truth_;
  TimeNs every_ns_;
  TimeNs next_ns_ = -1;
  bool batch_;
  std::vector<Row> rows_;
};

void Run(const Options& o, bool initial_trust_region_given) {
  io::CheckOutputsSpareInputs(
      {{o.out, "--out"}, {o.trajectory_out, "--trajectory-out"}, {o.track_out, "--track-out"}},
      {{o.dataset, "DIR"}});
  const AlgorithmOptions config = o.config.Load();
  const io::Dataset dataset = io::ReadDataset(o.dataset);
  const mapping::MapperOptions mapper_options =
      MapperOptionsOf(o, config, initial_trust_region_given);
  std::optional<SE2> init;
  if (!o.init.empty()) init = ParsePose(o.init, "--init");
  const auto start = std::chrono::steady_clock::now();
  std::string faults_seen;
  std::optional<Track> track;
  MapperWatch watch;
  if (!o.track_out.empty()) {
    track.emplace(dataset, o.track_every_s, o.track_batch);
    watch = [&track](const mapping::Mapper& m, TimeNs t_ns) { track->Watch(m, t_ns); };
  }
  mapping::Mapper mapper =
      BuildMap(dataset, mapper_options, init, true, o.pixels.Stream(o.dataset, config.front_end),
               &faults_seen, watch);
  const double total_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  io::WriteMap(o.out, mapper.Map());
  if (!o.trajectory_out.empty()) {
    io::WriteTum(o.trajectory_out, mapper.KeyframeTrajectory());
  }
  std::printf("%s\n", DescribeMapping(mapper, total_s).c_str());
  if (track) {
    track->Write(o.track_out);
    std::printf("%s; written to %s\n", track->Describe().c_str(), o.track_out.c_str());
  }
  if (!faults_seen.empty()) std::printf("%s\n", faults_seen.c_str());
  std::printf("map written to %s\n", o.out.c_str());
}

}  // namespace map_command

void AddMapCommand(CLI::App& app) {
  using namespace map_command;
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "map",
      "Build the semantic map (slots with IDs, tags) of a dataset: association by ID and "
      "nearest neighbour, a factor graph with rectangular slot constraints and a Max-Mixture "
      "back-end");
  cmd->add_option("DIR", options->dataset, "Dataset folder")->required();
  cmd->add_option("--out", options->out, "Map JSON to write")->required();
  cmd->add_option("--trajectory-out", options->trajectory_out,
                  "TUM file for the optimized keyframe trajectory");
  cmd->add_option("--robust", options->robust,
                  "maxmix: Max-Mixture back-end; none: the plain Gaussian graph (the paper's "
                  "baseline)")
      ->check(CLI::IsMember({"maxmix", "none"}))
      ->capture_default_str();
  cmd->add_option("--mode", options->mode,
                  "online: a bounded windowed update per keyframe and the full graph solved in "
                  "the background every 2 s of drive (the map at any moment as good as batch "
                  "so far); batch: a full optimization at the end")
      ->check(CLI::IsMember({"online", "batch"}))
      ->capture_default_str();
  cmd->add_option("--solver", options->solver, "Trust region of the final solve: lm or dogleg")
      ->check(CLI::IsMember({"lm", "dogleg"}))
      ->capture_default_str();
  cmd->add_option("--initial-trust-region", options->initial_trust_region,
                  "Initial trust-region radius of the final solve")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            double v = 0.0;
            if (!CLI::detail::lexical_cast(text, v) || !(v >= 1e-32 && v <= 1e16)) {
              return "must be a number from 1e-32 to 1e16 (the solver's own bounds), got " + text;
            }
            return "";
          },
          "1e-32..1e16"))
      ->capture_default_str();
  cmd->add_option("--track-out", options->track_out,
                  "CSV of the map as it stands along the drive (the slots seen twice), scored "
                  "against the dataset's ground truth every --track-every-s");
  cmd->add_option("--track-every-s", options->track_every_s,
                  "Seconds of drive between the --track-out rows")
      ->check(CLI::Range(0.1, 3600.0))
      ->capture_default_str();
  cmd->add_flag("--track-batch", options->track_batch,
                "Also score, at each --track-out row, the map a batch solve of the drive so far "
                "would give (a full solve a row)");
  AddPixelOptions(cmd, &options->pixels);
  AddConfigOptions(cmd, &options->config);
  cmd->add_option("--init", options->init,
                  "Known start pose x,y,yaw in the map frame (metres, radians); without it the "
                  "map frame starts at the first pose");
  cmd->callback([options, cmd] { Run(*options, cmd->count("--initial-trust-region") > 0); });
}

}  // namespace parkslam::app
