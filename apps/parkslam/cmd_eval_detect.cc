#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "commands.h"
#include "detection_scoring.h"
#include "image_files.h"
#include "parkslam/eval/detection_metrics.h"
#include "parkslam/harness/perception_eval.h"
#include "parkslam/io/output_guard.h"
#include "parkslam/io/ps2_labels.h"
#include "parkslam/perception/front_end.h"
#include "parkslam/perception/learned_slot_detector.h"
#include "parkslam/perception/slot_detector.h"
#include "parkslam/sim/simulator.h"
#include "progress.h"

namespace parkslam::app {
namespace eval_detect_command {

struct Options {
  ScenarioOptions scenario;
  std::uint64_t seed = 1;
  std::string ps2, out_dir;
  double rate_hz = 0.5;
  int max_frames = 0;
  bool json = false;
  std::string detector;  // --detector; empty: the configuration's front_end.detector
  std::string models;
  std::string classical_check = "none";
  int input_size = 256;
  int flips = 1;
  double min_confidence = 0.0;
  ConfigOptions config;
  // Given on the command line (else the network's own).
  bool input_size_given = false, flips_given = false;
};

void AddFlags(CLI::App* cmd, Options* options) {
  AddScenarioOptions(cmd, &options->scenario);
  cmd->add_option("--seed", options->seed, "Drive seed")
      ->check(SeedValidator())
      ->capture_default_str();
  cmd->add_option("--rate-hz", options->rate_hz, "Frames per second of the drive to score")
      ->check(CLI::Range(0.01, 30.0))
      ->capture_default_str();
  cmd->add_option("--max-frames", options->max_frames, "Score at most this many frames (0: all)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--ps2", options->ps2,
                  "Folder of ps2.0 images (*.jpg) with their labels (*.json) to score instead");
  cmd->add_option(
      "--out-dir", options->out_dir,
      "Write an overlay (truth green, detections red) of every image with an error, and for "
      "simulated frames the top view itself (N_top.png)");
  cmd->add_flag("--json", options->json, "Print one JSON object");
  cmd->add_option("--detector", options->detector,
                  "Slot detector and ID reader: learned (the networks of models/) or classical "
                  "(lines and corners); default: front_end.detector of --config, learned")
      ->check(CLI::IsMember({"classical", "learned"}));
  cmd->add_option("--models", options->models,
                  "Folder holding marking_points.onnx and slot_ids.onnx for --detector learned "
                  "(default: the committed ones)");
  cmd->add_option("--classical-check", options->classical_check,
                  "With --detector learned: what the classical detector does with the network's "
                  "marking points: none, refine (takes the position and direction of a point it "
                  "also found) or filter (refine, and drop the points it did not find); the slots' "
                  "corners are refined on the paint in every case")
      ->check(CLI::IsMember({"none", "refine", "filter"}))
      ->capture_default_str();
  cmd->add_option("--input-size", options->input_size,
                  "With --detector learned: the marking-point network's input, pixels (a multiple "
                  "of 16; the network was trained at 256)")
      ->check(CLI::Range(64, 1024))
      ->capture_default_str();
  cmd->add_option(
         "--flips", options->flips,
         "With --detector learned: test-time flips of the marking-point network: 1 (none), "
         "2 (left-right) or 4 (left-right, up-down and both), averaged")
      ->check(CLI::IsMember({1, 2, 4}))
      ->capture_default_str();
  cmd->add_option("--min-confidence", options->min_confidence,
                  "With --detector learned: the marking-point threshold (default: the network's, "
                  "chosen on the synthetic validation set)")
      ->check(CLI::Range(0.01, 0.99));
  AddConfigOptions(cmd, &options->config);
}

// The front end's options: --config, then the learned detector's flags.
perception::PerceptionOptions PerceptionOf(const Options& o) {
  perception::PerceptionOptions perception_options = o.config.Load().front_end;
  if (!o.detector.empty()) perception_options.detector = perception::ParseDetectorKind(o.detector);
  if (!o.models.empty()) {
    perception_options.learned_slots.model_path = o.models + "/marking_points.onnx";
    perception_options.learned_ids.model_path = o.models + "/slot_ids.onnx";
  }
  if (o.input_size_given) {
    perception_options.learned_slots.input_size_px = o.input_size;
  }
  if (o.flips_given) perception_options.learned_slots.flips = o.flips;
  if (o.min_confidence > 0.0) {
    perception_options.learned_slots.min_confidence = o.min_confidence;
  }
  perception_options.learned_slots.classical =
      o.classical_check == "filter"   ? perception::ClassicalCheck::kFilter
      : o.classical_check == "refine" ? perception::ClassicalCheck::kRefine
                                      : perception::ClassicalCheck::kNone;
  return perception_options;
}

// ps2.0 views: 600 px for 10 m, no footprint mask, no IDs to score.
void ScorePs2(const Options& o, const perception::PerceptionOptions& perception_options,
              Scores* scores) {
  std::unique_ptr<perception::SlotDetector> classical;
  std::unique_ptr<perception::LearnedSlotDetector> learned;
  if (perception_options.detector == perception::DetectorKind::kLearned) {
    perception::LearnedSlotDetectorOptions learned_options = perception_options.learned_slots;
    if (learned_options.model_path.empty())
      learned_options.model_path = perception::DefaultModelDir() + "/marking_points.onnx";
    learned = std::make_unique<perception::LearnedSlotDetector>(learned_options);
  } else {
    classical = std::make_unique<perception::SlotDetector>(perception_options.slots);
  }
  const auto detect = [&](const cv::Mat& image) {
    return learned ? learned->Detect(image) : classical->Detect(image);
  };
  const std::vector<std::string> names = io::ListPs2Images(o.ps2);
  if (names.empty()) throw std::runtime_error(o.ps2 + ": no labelled ps2.0 images");
  for (const std::string& name : names) {
    const std::filesystem::path image_path = std::filesystem::path(o.ps2) / (name + ".jpg");
    const io::Ps2Labels labels =
        io::ReadPs2Labels(std::filesystem::path(image_path).replace_extension(".json").string());
    const cv::Mat image = ReadImage(image_path.string(), cv::IMREAD_COLOR);
    const auto start = std::chrono::steady_clock::now();
    const perception::SlotDetection detection = detect(image);
    scores->slots_ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count());
    std::vector<eval::LabelledMarkingPoint> points;
    for (const io::Ps2MarkingPoint& p : labels.marking_points) {
      points.push_back({p.px, p.direction_rad, p.is_t});
    }
    std::vector<eval::LabelledSlot> slots;
    for (const io::Ps2Slot& s : labels.slots) slots.push_back({s.a, s.b});
    ImageTruth truth;
    truth.points = points;
    truth.entrances = eval::EntranceLinesOf(points, slots);
    const bool error = Score(truth, detection, {}, 60.0, scores).any_error();
    if (error && !o.out_dir.empty()) {
      WriteImage((std::filesystem::path(o.out_dir) / (name + ".png")).string(),
                 Overlay(image, points, detection, truth.entrances));
    }
  }
}

// Top views rendered along a simulated drive, against the simulator's truth.
void ScoreDrive(const Options& o, const perception::PerceptionOptions& perception_options,
                Scores* scores) {
  const DriveScorer drive(ResolveScenario(o.scenario), o.seed, perception_options);
  const Trajectory& truth = drive.truth();
  const TimeNs period = FromSeconds(1.0 / o.rate_hz);
  int total = static_cast<int>((truth.back().t_ns - truth.front().t_ns) / period) + 1;
  if (o.max_frames > 0) total = std::min(total, o.max_frames);
  Progress bar("  scoring", total);
  for (int k = 0; k < total; ++k) {
    const DriveScorer::Frame frame = drive.ScoreAt(truth.front().t_ns + period * k, scores);
    const perception::PerceptionOutput& out = frame.out;
    scores->fusion_ms.push_back(out.timing.fusion_ms);
    scores->slots_ms.push_back(out.timing.slots_ms);
    scores->ids_ms.push_back(out.timing.ids_ms);
    scores->tags_ms.push_back(out.timing.tags_ms);
    scores->frame_ms.push_back(out.timing.total_ms());
    if (frame.score.any_error() && !o.out_dir.empty()) {
      const std::filesystem::path base = std::filesystem::path(o.out_dir) / std::to_string(k);
      WriteImage(base.string() + "_overlay.png",
                 Overlay(out.top_view, frame.truth_points, out.detection, frame.truth_entrances));
      WriteImage(base.string() + "_top.png", out.top_view);
    }
    bar.Update(k + 1);
  }
  bar.Finish();
}

void Run(const Options& o) {
  io::CheckOutputsSpareInputs({{o.out_dir, "--out-dir", true}},
                              {{o.ps2, "--ps2"}, {o.models, "--models"}});
  Scores scores;
  if (!o.out_dir.empty()) std::filesystem::create_directories(o.out_dir);
  const perception::PerceptionOptions perception_options = PerceptionOf(o);
  if (!o.ps2.empty()) {
    ScorePs2(o, perception_options, &scores);
  } else {
    ScoreDrive(o, perception_options, &scores);
  }
  if (o.json) {
    std::cout << ToJson(scores).dump() << "\n";
  } else {
    Print(scores);
  }
}

}  // namespace eval_detect_command

void AddEvalDetectCommand(CLI::App& app) {
  using namespace eval_detect_command;
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "eval-detect",
      "Score the slot detector and ID reader with the DMPR-PS rule (10 px, 30 degrees at 600 px "
      "for 10 m): on top views rendered along a simulated drive against the simulator's truth, "
      "or on labelled ps2.0 images (--ps2)");
  AddFlags(cmd, options.get());
  cmd->callback([options, cmd] {
    options->input_size_given = cmd->count("--input-size") > 0;
    options->flips_given = cmd->count("--flips") > 0;
    Run(*options);
  });
}

}  // namespace parkslam::app
