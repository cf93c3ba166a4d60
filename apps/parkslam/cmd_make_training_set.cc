// parkslam make-training-set: randomized, labelled top views (and slot-ID
// crops) for training perception and for the hard evaluation set
// (docs/training_data.md).

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "commands.h"
#include "image_files.h"
#include "interruption.h"
#include "parkslam/camera/camera_model.h"
#include "parkslam/common/seed_mix.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/ps2_labels.h"
#include "parkslam/scene/font_book.h"
#include "parkslam/scene/labels.h"
#include "parkslam/scene/scene.h"
#include "parkslam/scene/scene_renderer.h"
#include "progress.h"

namespace parkslam::app {
namespace make_training_set_command {

struct Options {
  std::string out;
  int count = 100;
  std::uint64_t seed = 1;
  std::string kind = "top-view";
  int threads = 0;
  double seven_segment_share = 0.0;
  double coarse_sensor_share = scene::SceneSamplerOptions{}.coarse_sensor_share;
  double nearest_lookup_share = scene::SceneSamplerOptions{}.nearest_lookup_share;
  double ray_seam_share = scene::SceneSamplerOptions{}.ray_seam_share;
  double chroma_noise_share = scene::SceneSamplerOptions{}.chroma_noise_share;
  double fisheye_scale = 1.0;
  std::string fonts = "/usr/share/fonts";
  bool fisheyes = false, front = false, overlays = false, force = false;
};

std::string Name(int index) {
  char name[16];
  std::snprintf(name, sizeof(name), "%06d", index);
  return name;
}

void WriteJpeg(const std::filesystem::path& path, const cv::Mat& image, int quality) {
  std::vector<std::uint8_t> bytes;
  if (!cv::imencode(".jpg", image, bytes, {cv::IMWRITE_JPEG_QUALITY, quality})) {
    throw std::runtime_error(path.string() + ": could not encode the image");
  }
  io::WriteFileAtomically(
      path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

io::Ps2Labels ToPs2(const scene::TopViewLabels& labels) {
  io::Ps2Labels ps2;
  for (const scene::LabelledMark& m : labels.marks) {
    io::Ps2MarkingPoint p;
    p.px = m.px;
    p.direction_rad = m.direction_rad;
    p.is_t = m.is_t;
    ps2.marking_points.push_back(p);
  }
  for (const scene::LabelledSlot& s : labels.slots) {
    io::Ps2Slot slot;
    slot.a = s.a;
    slot.b = s.b;
    slot.type = s.kind == scene::SlotKind::kParallel ? 2 : 1;
    slot.angle_deg = s.angle_deg;
    ps2.slots.push_back(slot);
  }
  return ps2;
}

// --kind and --out checked: refused when --out is a file, or a folder that
// is not empty unless --force. True when --force writes into a folder that
// holds files already (in place: they are kept beside the new ones).
bool CheckOutput(const Options& o) {
  namespace fs = std::filesystem;
  if (o.kind != "top-view" && o.kind != "ids") {
    throw std::invalid_argument("--kind: expected top-view or ids, got '" + o.kind + "'");
  }
  const fs::path out = o.out;
  std::error_code ec;
  if (fs::exists(out, ec) && !fs::is_directory(out, ec)) {
    throw std::runtime_error(o.out + ": exists and is not a folder");
  }
  const bool holds_files = fs::is_directory(out, ec) && !fs::is_empty(out, ec);
  if (holds_files && !o.force) {
    throw std::runtime_error(o.out + ": the folder is not empty (pass --force to write into it)");
  }
  return holds_files;
}

// The floor's fonts under --fonts (none: OpenCV's stroke fonts, with a word).
std::vector<std::filesystem::path> FloorFonts(const Options& o) {
  std::error_code ec;
  if (!std::filesystem::is_directory(o.fonts, ec))
    throw std::runtime_error("--fonts: " + o.fonts + ": not a folder");
  const std::vector<std::filesystem::path> fonts = scene::FindFloorFonts(o.fonts);
  if (fonts.empty()) {
    std::fprintf(stderr,
                 "make-training-set: no font files under %s; IDs use OpenCV's stroke fonts only\n",
                 o.fonts.c_str());
  }
  return fonts;
}

// What each scene gave, by scene index, for the summary and ids/labels.csv.
struct SceneCounts {
  std::vector<std::vector<std::string>> id_rows;
  std::vector<int> mark_counts, slot_counts;
  explicit SceneCounts(int count)
      : id_rows(static_cast<size_t>(count)),
        mark_counts(static_cast<size_t>(count), 0),
        slot_counts(static_cast<size_t>(count), 0) {}
};

// Scene i sampled, rendered, labelled and written with what the options ask.
void WriteScene(const Options& o, const scene::SceneRenderer& renderer, scene::FontBook* book,
                const scene::RenderRequest& request, int i, SceneCounts* counts) {
  const std::filesystem::path out = o.out;
  const bool ids = o.kind == "ids";
  scene::SceneSamplerOptions sampler;
  sampler.seven_segment_share = o.seven_segment_share;
  sampler.coarse_sensor_share = o.coarse_sensor_share;
  sampler.nearest_lookup_share = o.nearest_lookup_share;
  sampler.ray_seam_share = o.ray_seam_share;
  sampler.chroma_noise_share = o.chroma_noise_share;
  const scene::Scene s =
      scene::SampleScene(MixSeed(o.seed, static_cast<std::uint64_t>(i)), sampler);
  const scene::RenderedScene r = renderer.Render(s, book, request);
  const scene::TopViewLabels labels = scene::LabelTopView(renderer, s, r);
  const std::string name = Name(i);
  counts->mark_counts[static_cast<size_t>(i)] = static_cast<int>(labels.marks.size());
  counts->slot_counts[static_cast<size_t>(i)] = static_cast<int>(labels.slots.size());
  if (ids) {
    for (size_t k = 0; k < labels.ids.size(); ++k) {
      const std::string file = "ids/" + name + "_" + std::to_string(k) + ".png";
      WriteImage((out / file).string(), labels.ids[k].image);
      counts->id_rows[static_cast<size_t>(i)].push_back(file + "," + labels.ids[k].text);
    }
  } else {
    WriteJpeg(out / (name + ".jpg"), r.top_view, s.top_view_jpeg_quality);
    io::WriteFileAtomically(out / (name + ".json"),
                            io::Ps2LabelsToJson(ToPs2(labels)).dump() + "\n");
  }
  if (o.fisheyes) {
    const std::vector<std::string>& names = renderer.options().fisheye_names;
    for (size_t c = 0; c < r.fisheyes.size(); ++c) {
      WriteJpeg(out / "fisheye" / (name + "_" + names[c] + ".jpg"), r.fisheyes[c], 92);
    }
  }
  if (o.front && !r.front.empty()) WriteJpeg(out / "front" / (name + ".jpg"), r.front, 92);
  if (o.overlays)
    WriteJpeg(out / "overlays" / (name + ".jpg"), scene::DrawLabels(r.top_view, labels, s), 90);
}

void WriteManifest(const Options& o, const std::vector<std::filesystem::path>& fonts, int marks,
                   int slots, int id_count) {
  nlohmann::json manifest;
  manifest["generator"] = "parkslam make-training-set";
  manifest["version"] = kVersion;
  manifest["kind"] = o.kind;
  manifest["seed"] = o.seed;
  manifest["count"] = o.count;
  manifest["scene_seed"] = "MixSeed(seed, index) of common/seed_mix.h";
  manifest["marking_points"] = marks;
  manifest["slots"] = slots;
  manifest["id_crops"] = id_count;
  nlohmann::json font_names = nlohmann::json::array();
  for (const std::filesystem::path& f : fonts) font_names.push_back(f.filename().string());
  manifest["fonts"] = font_names;
  io::WriteFileAtomically(std::filesystem::path(o.out) / "manifest.json", manifest.dump(2) + "\n");
}

void Run(const Options& given) {
  namespace fs = std::filesystem;
  const bool in_place = CheckOutput(given);
  // A new or empty --out is written as a staging folder beside it and moved
  // there once whole: an interrupted or failed run leaves nothing (a killed
  // one leaves the staging folder, which the next run's sweep removes).
  // --force into a folder with files writes in place, beside them.
  Options o = given;
  std::optional<io::TemporaryFile> staging;
  if (!in_place) {
    staging.emplace(StagingTarget(given.out), io::TemporaryFile::Kind::kFolder);
    o.out = staging->path().string();
  }
  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (ec) throw std::runtime_error(given.out + ": cannot create the folder: " + ec.message());
  const InterruptionScope interruption;
  const fs::path out = o.out;
  const std::vector<fs::path> fonts = FloorFonts(o);
  // The workers are the parallelism: OpenCV's own threads would only contend.
  cv::setNumThreads(1);
  const auto t_setup = std::chrono::steady_clock::now();
  const scene::SceneRenderer renderer(
      camera::WithFisheyeResolution(camera::DefaultRig(), o.fisheye_scale));
  const int threads = o.threads > 0
                          ? o.threads
                          : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  renderer.BuildFusions(threads, o.ray_seam_share > 0);
  const double setup_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_setup).count();
  const bool ids = o.kind == "ids";
  if (ids) fs::create_directories(out / "ids");
  if (o.fisheyes) fs::create_directories(out / "fisheye");
  if (o.front) fs::create_directories(out / "front");
  if (o.overlays) fs::create_directories(out / "overlays");

  SceneCounts counts(o.count);
  std::atomic<int> next{0}, done{0};
  std::mutex error_mutex;
  std::string error;
  Progress progress("make-training-set", o.count);
  const auto start = std::chrono::steady_clock::now();
  const auto work = [&] {
    scene::FontBook book(fonts);
    scene::RenderRequest request;
    request.solids = true;
    request.front = o.front;
    request.fisheyes = o.fisheyes;
    try {
      for (int i = next++; i < o.count; i = next++) {
        InterruptionScope::ThrowIfInterrupted("nothing was written to --out");
        WriteScene(o, renderer, &book, request, i, &counts);
        const int finished = ++done;
        if (finished % 4 == 0 || finished == o.count) {
          std::lock_guard<std::mutex> lock(error_mutex);
          progress.Update(finished);
        }
      }
    } catch (const std::exception& e) {
      std::lock_guard<std::mutex> lock(error_mutex);
      if (error.empty()) error = e.what();
      next = o.count;
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) pool.emplace_back(work);
  for (std::thread& t : pool) t.join();
  // In this thread, so that main() sees the signal (exit 128 + it).
  InterruptionScope::ThrowIfInterrupted(in_place ? "--out holds the scenes written so far"
                                                 : "nothing was written to --out");
  if (!error.empty()) throw std::runtime_error(error);
  progress.Finish();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  int marks = 0, slots = 0, id_count = 0;
  for (int i = 0; i < o.count; ++i) {
    marks += counts.mark_counts[static_cast<size_t>(i)];
    slots += counts.slot_counts[static_cast<size_t>(i)];
    id_count += static_cast<int>(counts.id_rows[static_cast<size_t>(i)].size());
  }
  if (ids) {
    std::ostringstream csv;
    csv << "file,text\n";
    for (const auto& rows : counts.id_rows) {
      for (const std::string& row : rows) csv << row << "\n";
    }
    io::WriteFileAtomically(out / "ids" / "labels.csv", csv.str());
  }
  WriteManifest(o, fonts, marks, slots, id_count);
  if (staging) staging->Commit();
  std::printf(
      "%d %s in %.1f s on %d threads: %.1f images/s, %.1f per thread (setup %.1f s); %d marking "
      "points, %d slots, %d ID crops\n",
      o.count, ids ? "scenes" : "top views", seconds, threads, o.count / seconds,
      o.count / seconds / threads, setup_s, marks, slots, id_count);
}

}  // namespace make_training_set_command

void AddMakeTrainingSetCommand(CLI::App& app) {
  using namespace make_training_set_command;
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "make-training-set",
      "Render randomized, labelled top views for training and hard evaluation "
      "(docs/training_data.md). --kind top-view writes NNNNNN.jpg with NNNNNN.json labels in the "
      "ps2.0 / DMPR-PS form (eval-detect --ps2 reads the folder); --kind ids writes crops of "
      "painted slot IDs with ids/labels.csv. Deterministic by --seed (on one set of fonts).");
  cmd->add_option("--out", options->out, "Folder to write (must be empty unless --force)")
      ->required();
  cmd->add_option("--count", options->count, "Number of scenes")
      ->check(CLI::Range(1, 10000000))
      ->capture_default_str();
  cmd->add_option("--seed", options->seed, "Seed of the set; scene i uses MixSeed(seed, i)")
      ->check(SeedValidator())
      ->capture_default_str();
  cmd->add_option("--kind", options->kind, "top-view or ids")->capture_default_str();
  cmd->add_option("--threads", options->threads, "Worker threads (0: one per core)")
      ->check(CLI::Range(0, 256))
      ->capture_default_str();
  cmd->add_option("--seven-segment-share", options->seven_segment_share,
                  "Share of slot rows whose IDs are digits in the default lot's seven-segment face "
                  "(0 leaves every scene as before)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--coarse-sensor-share", options->coarse_sensor_share,
                  "Share of scenes whose cameras have a coarse sensor (far lines smear)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--nearest-lookup-share", options->nearest_lookup_share,
                  "Share of scenes whose fusion takes the nearest camera pixel instead of "
                  "interpolating (sharp, jagged lines; 0 leaves every scene as before)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--ray-seam-share", options->ray_seam_share,
                  "Share of scenes whose seams are straight rays from the car's corners, as "
                  "ps2.0's views show them (0 leaves every scene as before)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--chroma-noise-share", options->chroma_noise_share,
                  "Share of scenes whose cameras show chroma noise, colour blotches a few pixels "
                  "across as cheap sensors leave them (0 leaves every scene as before)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--fisheye-scale", options->fisheye_scale,
                  "The fisheyes' resolution relative to the simulator's 640 x 480 (2: 1280 x "
                  "960, as sharp as many surround-view units' cameras), same field of view")
      ->check(CLI::Range(0.25, 4.0))
      ->capture_default_str();
  cmd->add_option(
         "--fonts", options->fonts,
         "Folder searched (recursively, in sorted order) for the floor's .ttf and .otf fonts; "
         "a copy of /usr/share/fonts that keeps its sub-folders gives the same scenes")
      ->capture_default_str();
  cmd->add_flag("--fisheyes", options->fisheyes,
                "Also write the four fisheye images of each scene");
  cmd->add_flag("--front", options->front, "Also write the front camera's image");
  cmd->add_flag("--overlays", options->overlays, "Also write the labels drawn over each top view");
  cmd->add_flag("--force", options->force, "Write into a folder that is not empty");
  cmd->callback([options] { Run(*options); });
}

}  // namespace parkslam::app
