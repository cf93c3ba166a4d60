#ifndef PARKSLAM_APPS_COMMANDS_H_
#define PARKSLAM_APPS_COMMANDS_H_

#include <CLI/CLI.hpp>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "parkslam/common/se2.h"
#include "parkslam/harness/fault_injection.h"
#include "parkslam/harness/sensor_stream.h"
#include "parkslam/io/output_guard.h"
#include "parkslam/io/pose_text.h"
#include "parkslam/options/algorithm_options.h"
#include "parkslam/perception/front_end.h"
#include "parkslam/sim/scenario_config.h"

namespace parkslam::app {

inline constexpr const char* kVersion = "0.1.0";

// Each subcommand registers itself; its callback throws on failure and
// main() turns the exception into a message and a non-zero exit code.
void AddSimulateCommand(CLI::App& app);
void AddOdometryCommand(CLI::App& app);
void AddEvalTrajCommand(CLI::App& app);
void AddDemoCommand(CLI::App& app);
void AddMapCommand(CLI::App& app);
void AddUpdateMapCommand(CLI::App& app);
void AddEvalMapCommand(CLI::App& app);
void AddRenderCommand(CLI::App& app);
void AddPlanFromMapCommand(CLI::App& app);
void AddLocalizeCommand(CLI::App& app);
void AddFollowCommand(CLI::App& app);
void AddTopviewCommand(CLI::App& app);
void AddTagsCommand(CLI::App& app);
void AddDetectCommand(CLI::App& app);
void AddEvalDetectCommand(CLI::App& app);
void AddMakeTrainingSetCommand(CLI::App& app);
void AddReportCommand(CLI::App& app);
void AddCheckDatasetCommand(CLI::App& app);
void AddSolveGraphCommand(CLI::App& app);
void AddMakeGraphCommand(CLI::App& app);
#ifdef PARKSLAM_HAVE_ROSBAG
void AddImportRosbagCommand(CLI::App& app);
void AddExportRosbagCommand(CLI::App& app);
#endif

// The command line as the user typed it (main() records it), for the
// records a run leaves (metrics.json, report.html).
void SetCommandLine(int argc, char** argv);
const std::string& CommandLine();

// Writes the HTML report of a run folder (cmd_report.cc); `map_path` may
// name a map outside the folder (follow runs).
struct ReportInputs {
  std::filesystem::path map;      // default: DIR/map.json
  std::filesystem::path dataset;  // the map's ground truth; default: DIR/dataset
};
void WriteReport(const std::filesystem::path& dir, const ReportInputs& inputs,
                 const std::filesystem::path& out);

// Options shared by `simulate` and `demo` that pick and tune the scenario.
struct ScenarioOptions {
  std::string world = "default";
  std::string plan;  // a world plan file instead of --world
  std::vector<std::string> overrides;
  double id_confusion_rate = -1.0;  // < 0: keep the scenario's
  double id_partial_rate = -1.0;
  std::string look;  // a look's name or a seed ("": the scenario's)
};
void AddScenarioOptions(CLI::App* command, ScenarioOptions* options);
// The files the scenario is read from (--world, --plan), named as the user
// gave them, for io::CheckOutputsSpareInputs.
std::vector<io::NamedPath> ScenarioFiles(const ScenarioOptions& options);

// A seed: a whole number from 0 to 2^64 - 1, written as such ("-1" would
// otherwise wrap around to 2^64 - 1 without a word).
const CLI::Validator& SeedValidator();
sim::ScenarioConfig ResolveScenario(const ScenarioOptions& options);

// Where the cameras' frames come from for `map` and `localize`: rendered
// live at a rate, or the dataset's own images.
// --config FILE.yaml (the algorithm options, io/options_yaml.h) and
// --dump-config (print their defaults and exit).
struct ConfigOptions {
  std::string file;
  // The defaults overlaid with --config; throws IoError naming the file and
  // the key.
  AlgorithmOptions Load() const;
};
void AddConfigOptions(CLI::App* command, ConfigOptions* options);

struct PixelOptions {
  double live_images_hz = 0.0;
  bool images = false;
  std::string detector;             // --detector; empty: the configuration's front_end.detector
  std::vector<std::string> faults;  // --fault, as written
  // The front end's options (from --config, else the defaults) with the
  // chosen detector.
  perception::PerceptionOptions Perception(const perception::PerceptionOptions& base = {}) const;
  // The parsed --fault options; throws std::runtime_error naming the bad one.
  std::vector<harness::SensorFault> Faults() const;
  // Where the stream's slots and tags come from: --images (dataset_dir's
  // own), --live-images, or the dataset's observations.
  harness::FrameSource Frames(const std::filesystem::path& dataset_dir) const;
  // The stream these options ask for over the dataset in dataset_dir.
  harness::StreamOptions Stream(const std::filesystem::path& dataset_dir,
                                const perception::PerceptionOptions& base = {}) const;
};
// --detector: which slot detector and ID reader a command on pixels runs.
void AddDetectorOption(CLI::App* command, std::string* detector);
void AddPixelOptions(CLI::App* command, PixelOptions* options);

// A dataset's --out folder: refused when it is a file, or a folder that is
// not empty unless `force`, which clears it (another drive's data or images
// would mix with the new one's). `force` clears only what looks like a
// dataset (dataset.yaml, and nothing but a dataset's folders beside it).
void PrepareDatasetFolder(const std::string& out, bool force);
// The same checks without clearing: true when the folder holds a dataset
// that `force` allows to be cleared.
bool CheckDatasetFolder(const std::string& out, bool force);
void ClearDatasetFolder(const std::string& out);
// Where an output folder's staging folder goes (io::TemporaryFile of kind
// kFolder, written whole and then moved to `out`): `out` without a trailing
// separator, its parent folder made.
std::filesystem::path StagingTarget(const std::string& out);

// "x,y,yaw" (metres, metres, radians), as io/pose_text.h reads it.
using io::ParsePose;

}  // namespace parkslam::app

#endif  // PARKSLAM_APPS_COMMANDS_H_
