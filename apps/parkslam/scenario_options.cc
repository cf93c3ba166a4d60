#include <algorithm>
#include <iostream>
#include <stdexcept>

#include "commands.h"
#include "parkslam/io/options_yaml.h"
#include "parkslam/io/scenario_yaml.h"
#include "parkslam/io/text_util.h"
#include "parkslam/io/world_plan_yaml.h"
#include "parkslam/options/option_ranges.h"

namespace parkslam::app {

const CLI::Validator& SeedValidator() {
  static const CLI::Validator validator(
      [](const std::string& text) -> std::string {
        const std::string max = "18446744073709551615";
        if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos ||
            text.size() > max.size() || (text.size() == max.size() && text > max)) {
          return "a seed is a whole number from 0 to 18446744073709551615, got '" + text + "'";
        }
        return "";
      },
      "SEED");
  return validator;
}

void AddScenarioOptions(CLI::App* command, ScenarioOptions* options) {
  CLI::Option* world = command
                           ->add_option("--world", options->world,
                                        "Built-in world `default` or a scenario YAML file")
                           ->capture_default_str();
  command
      ->add_option("--plan", options->plan,
                   "A world plan YAML instead: slots, walls, pillars and tags listed one by one, "
                   "and a route as waypoints (docs/world_plan.md, config/plans/)")
      ->check(CLI::ExistingFile)
      ->excludes(world);
  command
      ->add_option("--id-confusion-rate", options->id_confusion_rate,
                   "Share of ID readings with one digit confused (3/8, 1/7 ...)")
      ->check(CLI::Range(0.0, 1.0));
  command
      ->add_option("--id-partial-rate", options->id_partial_rate,
                   "Share of ID readings with one digit unread")
      ->check(CLI::Range(0.0, 1.0));
  command->add_option("--look", options->look,
                      "How the cameras see the lot: grey (flat floor, seven-segment IDs), "
                      "epoxy, concrete, underground, outdoor, yellow, faded, or a number: a "
                      "look drawn from that seed (sets world.look and world.look_seed)");
  command->add_option("--set", options->overrides,
                      "Override a scenario key, e.g. --set route.laps=4 "
                      "--set sensors.slots.miss_rate=0.1 (repeatable)");
}

std::vector<io::NamedPath> ScenarioFiles(const ScenarioOptions& options) {
  std::vector<io::NamedPath> files;
  if (options.world != "default") files.push_back({options.world, "--world"});
  if (!options.plan.empty()) files.push_back({options.plan, "--plan"});
  return files;
}

sim::ScenarioConfig ResolveScenario(const ScenarioOptions& options) {
  sim::ScenarioConfig scenario = !options.plan.empty()        ? io::LoadPlanFile(options.plan)
                                 : options.world == "default" ? sim::DefaultScenario()
                                                              : io::LoadScenarioFile(options.world);
  if (options.id_confusion_rate >= 0.0) {
    scenario.sensors.ids.confusion_rate = options.id_confusion_rate;
  }
  if (options.id_partial_rate >= 0.0) {
    scenario.sensors.ids.partial_rate = options.id_partial_rate;
  }
  if (!options.look.empty()) {
    const bool number = options.look.find_first_not_of("0123456789") == std::string::npos;
    if (number && options.look.size() <= 9) {
      scenario.world.look = "seed";
      scenario.world.look_seed = std::stoi(options.look);
    } else {
      const std::vector<std::string>& names = sim::LookNames();
      if (std::find(names.begin(), names.end(), options.look) == names.end()) {
        std::string message = "--look: ";
        message.append(io::text::Quoted(options.look)).append(" is neither a look (");
        for (size_t i = 0; i < names.size(); ++i) message.append(i ? ", " : "").append(names[i]);
        message.append(") nor a seed of at most 9 digits");
        throw std::invalid_argument(message);
      }
      scenario.world.look = options.look;
    }
  }
  for (const std::string& assignment : options.overrides) {
    io::ApplyOverride(&scenario, assignment);
  }
  std::string error;
  if (!scenario.IsValid(&error)) {
    throw std::invalid_argument("invalid scenario: " + error);
  }
  return scenario;
}

void AddPixelOptions(CLI::App* command, PixelOptions* options) {
  command
      ->add_option("--live-images", options->live_images_hz,
                   "Run on pixels: render the simulated cameras on the fly at this rate (Hz), "
                   "writing nothing, and use the slots, IDs and tags the front end finds in "
                   "them instead of the dataset's detections (needs its ground truth)")
      ->check(CLI::Range(0.0, 30.0));
  command
      ->add_flag("--images", options->images,
                 "Run on the dataset's own images (DIR/images/, from simulate --images): the "
                 "slots, IDs and tags found in them replace the dataset's detections")
      ->excludes("--live-images");
  AddDetectorOption(command, &options->detector);
  command->add_option(
      "--fault", options->faults,
      "Inject a sensor fault into the stream (repeatable; docs/robustness.md): "
      "KIND@START+DURATION[,camera=NAME][,magnitude=X], seconds from the stream's start; KIND "
      "is camera-gap, camera-black, camera-frozen, late-frames, imu-spikes, heading-jump, "
      "wheel-dropout or clock-jitter (e.g. camera-black@60+20,camera=left)");
}

std::vector<harness::SensorFault> PixelOptions::Faults() const {
  std::vector<harness::SensorFault> parsed;
  for (const std::string& text : faults) {
    try {
      parsed.push_back(harness::ParseSensorFault(text));
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(std::string("--fault: ") + e.what());
    }
  }
  return parsed;
}

harness::FrameSource PixelOptions::Frames(const std::filesystem::path& dataset_dir) const {
  if (images) return harness::FromRecordedImages{dataset_dir};
  if (live_images_hz > 0.0) return harness::FromLiveRendering{live_images_hz};
  return harness::FromObservations{};
}

harness::StreamOptions PixelOptions::Stream(const std::filesystem::path& dataset_dir,
                                            const perception::PerceptionOptions& base) const {
  return {Frames(dataset_dir), Perception(base), Faults()};
}

void AddDetectorOption(CLI::App* command, std::string* detector) {
  command
      ->add_option("--detector", *detector,
                   "On pixels: the slot detector and ID reader, learned (the networks of "
                   "models/, docs/learned_perception.md) or classical (lines and corners, "
                   "seven-segment digits); default: front_end.detector of --config, learned")
      ->check(CLI::IsMember({"classical", "learned"}));
}

perception::PerceptionOptions PixelOptions::Perception(
    const perception::PerceptionOptions& base) const {
  perception::PerceptionOptions o = base;
  if (!detector.empty()) o.detector = perception::ParseDetectorKind(detector);
  return o;
}

AlgorithmOptions ConfigOptions::Load() const {
  return file.empty() ? AlgorithmOptions{} : io::LoadOptionsFile(file);
}

void AddConfigOptions(CLI::App* command, ConfigOptions* options) {
  command
      ->add_option("--config", options->file,
                   "Algorithm options (front end, mapper, localizer, follower) from a YAML file; "
                   "only the keys it gives change (see --dump-config, config/options.yaml)")
      ->check(CLI::ExistingFile);
  command->add_flag_callback(
      "--dump-config",
      [] {
        std::cout << io::OptionsToYaml(AlgorithmOptions{});
        throw CLI::Success();
      },
      "Print every algorithm option with its default as YAML and exit");
  command->add_flag_callback(
      "--dump-ranges",
      [] {
        std::cout << OptionRangesMarkdown();
        throw CLI::Success();
      },
      "Print every numeric algorithm option's plausible range (a Markdown table) and exit");
}

namespace {

// What simulate and import-rosbag write at the top of a dataset folder.
bool IsADatasetsEntry(const std::filesystem::path& entry) {
  const std::string name = entry.filename().string();
  for (const char* own : {"dataset.yaml", "sensors", "groundtruth", "observations", "images"}) {
    if (name == own) return true;
  }
  return false;
}

}  // namespace

bool CheckDatasetFolder(const std::string& out, bool force) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(out, ec) && !fs::is_directory(out, ec)) {
    throw std::runtime_error("--out " + out + ": a file, not a folder");
  }
  if (!fs::is_directory(out, ec) || fs::is_empty(out, ec)) return false;
  if (!force) {
    throw std::runtime_error("--out " + out +
                             ": the folder is not empty (another drive's data or images would "
                             "mix with this one's); choose another or add --force to clear it");
  }
  // --force clears a dataset, never a folder of something else.
  if (!fs::is_regular_file(fs::path(out) / "dataset.yaml", ec)) {
    throw std::runtime_error("--out " + out +
                             ": --force clears only a dataset folder (one with dataset.yaml, as "
                             "simulate and import-rosbag write), and this one has none");
  }
  for (const auto& entry : fs::directory_iterator(out)) {
    if (!IsADatasetsEntry(entry.path())) {
      throw std::runtime_error("--out " + out + ": --force clears only a dataset folder, and " +
                               entry.path().filename().string() +
                               " is not a dataset's; move it or choose another folder");
    }
  }
  return true;
}

void ClearDatasetFolder(const std::string& out) {
  std::error_code ec;
  if (!std::filesystem::is_directory(out, ec)) return;
  for (const auto& entry : std::filesystem::directory_iterator(out)) {
    std::filesystem::remove_all(entry.path());
  }
}

std::filesystem::path StagingTarget(const std::string& out) {
  std::filesystem::path target(out);
  if (!target.has_filename()) target = target.parent_path();
  if (target.has_parent_path()) std::filesystem::create_directories(target.parent_path());
  return target;
}

void PrepareDatasetFolder(const std::string& out, bool force) {
  if (CheckDatasetFolder(out, force)) ClearDatasetFolder(out);
}

}  // namespace parkslam::app
