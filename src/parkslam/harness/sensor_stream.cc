#include "parkslam/harness/sensor_stream.h"

#include <cstdio>
#include <stdexcept>
#include <utility>

#include "parkslam/camera/camera_names.h"
#include "parkslam/common/seed_mix.h"
#include "parkslam/harness/live_cameras.h"
#include "parkslam/harness/rendering_source.h"
#include "parkslam/io/dataset.h"
#include "parkslam/io/image_folder.h"
#include "parkslam/io/rig_yaml.h"
#include "parkslam/live/live_system.h"

namespace parkslam::harness {
namespace {

// The stream of injected faults draws from its own sequence.
constexpr std::uint64_t kFaultSeedTag = 0xFA17;

template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

}  // namespace

std::string Describe(const FrameSource& frames) {
  return std::visit(Overloaded{
                        [](const FromObservations&) { return std::string("observations"); },
                        [](const FromRecordedImages& r) {
                          return "recorded images in " + (r.dataset_dir / "images").string();
                        },
                        [](const FromLiveRendering& l) {
                          char text[64];
                          std::snprintf(text, sizeof text, "live rendering at %g Hz", l.rate_hz);
                          return std::string(text);
                        },
                    },
                    frames);
}

StreamInputs StreamInputs::Of(const io::Dataset& dataset) {
  StreamInputs in;
  in.name = dataset.name;
  in.seed = dataset.seed;
  in.log = &dataset.log;
  in.scenario = dataset.scenario ? &*dataset.scenario : nullptr;
  in.truth = &dataset.groundtruth_trajectory;
  return in;
}

// On pixels: where the camera frames come from, and the front end that
// turns them into slot and tag frames.
struct SensorStream::Pixels {
  std::unique_ptr<LiveCameras> cameras;                       // live rendering only
  std::unique_ptr<camera::CameraRig> rig;                     // recorded images only
  std::unique_ptr<perception::PerceptionFrontEnd> front_end;  // recorded images only
  std::unique_ptr<SensorSource> frames;                       // rendered or recorded
  std::unique_ptr<perception::PerceptionSource> perception;
  const perception::PerceptionFrontEnd* front_end_in_use = nullptr;
};

SensorStream::SensorStream(const io::Dataset& dataset, const StreamOptions& options)
    : SensorStream(StreamInputs::Of(dataset), options) {}

SensorStream::SensorStream(const StreamInputs& in, const StreamOptions& options)
    : log_(in.log != nullptr ? *in.log : throw std::invalid_argument(in.name + ": no sensor log")) {
  const std::uint64_t fault_seed = MixSeed(in.seed, kFaultSeedTag);
  if (std::holds_alternative<FromObservations>(options.frames)) {
    WithFaults(log_, fault_seed, options.faults);
    return;
  }
  pixels_ = std::make_unique<Pixels>();
  const perception::PerceptionFrontEnd* front_end = nullptr;
  if (const auto* recorded = std::get_if<FromRecordedImages>(&options.frames)) {
    io::ReadImageIndex(recorded->dataset_dir);  // names what is missing before the rig does
    pixels_->rig = std::make_unique<camera::CameraRig>(
        io::LoadRig(recorded->dataset_dir / "images" / "rig.yaml"));
    pixels_->frames = std::make_unique<io::ImageFolderSource>(
        log_, recorded->dataset_dir, *pixels_->rig, camera::AllCameraNames());
    pixels_->front_end =
        std::make_unique<perception::PerceptionFrontEnd>(*pixels_->rig, options.perception);
    front_end = pixels_->front_end.get();
  } else {
    const double rate_hz = std::get<FromLiveRendering>(options.frames).rate_hz;
    if (in.truth == nullptr || in.truth->size() < 2) {
      throw std::runtime_error(in.name + ": live images need the dataset's ground truth");
    }
    if (in.scenario == nullptr) {
      throw std::runtime_error(in.name +
                               ": live images render the simulated world, and this dataset has "
                               "no scenario (a recording); use its recorded images (--images)");
    }
    pixels_->cameras = std::make_unique<LiveCameras>(
        sim::BuildWorld(in.scenario->world), in.scenario->world, in.seed, options.perception);
    pixels_->frames = std::make_unique<RenderingSource>(
        log_, pixels_->cameras->renderer(), *in.truth, pixels_->cameras->cameras(), rate_hz);
    front_end = &pixels_->cameras->front_end();
  }
  // The front end's slot and tag frames replace the log's observation-level
  // ones.
  pixels_->perception = std::make_unique<perception::PerceptionSource>(
      WithFaults(*pixels_->frames, fault_seed, options.faults), *front_end);
  pixels_->front_end_in_use = front_end;
}

SensorStream::~SensorStream() = default;

SensorSource& SensorStream::WithFaults(SensorSource& inner, std::uint64_t seed,
                                       const std::vector<SensorFault>& faults) {
  if (faults.empty()) return inner;
  faults_ = std::make_unique<FaultInjectingSource>(inner, faults, seed);
  return *faults_;
}

SensorSource& SensorStream::source() {
  if (pixels_) return *pixels_->perception;
  if (faults_) return *faults_;
  return log_;
}

const InjectedFaults* SensorStream::injected() const {
  return faults_ ? &faults_->injected() : nullptr;
}

const perception::PerceptionSource* SensorStream::perception() const {
  return pixels_ ? pixels_->perception.get() : nullptr;
}

void SensorStream::SearchTagsFor(const localization::Localizer& localizer) {
  if (!pixels_) return;
  const perception::PerceptionFrontEnd* front_end = pixels_->front_end_in_use;
  pixels_->perception->SearchTagsIn([front_end, &localizer](TimeNs t_ns) {
    return live::MapTagWindows(*front_end, localizer, t_ns);
  });
}

std::string SensorStream::DescribeFaults() const {
  std::string out;
  if (faults_) {
    const InjectedFaults& f = faults_->injected();
    char line[512];
    std::snprintf(line, sizeof(line),
                  "faults injected: %d frames dropped, %d images black, %d frozen, %d frames "
                  "late, %d IMU spikes, %d headings shifted, %d wheel samples dropped, %d "
                  "events jittered",
                  f.frames_dropped, f.images_blackened, f.images_frozen, f.frames_delayed,
                  f.imu_spikes, f.heading_samples_shifted, f.wheel_samples_dropped,
                  f.events_jittered);
    out += line;
  }
  if (pixels_) {
    const perception::CameraHealthMonitor& health = pixels_->perception->camera_health();
    std::string cameras;
    for (const auto& [name, n] : health.black_images()) {
      cameras +=
          (cameras.empty() ? "" : ", ") + name + " black in " + std::to_string(n) + " frames";
    }
    for (const auto& [name, n] : health.frozen_images()) {
      cameras +=
          (cameras.empty() ? "" : ", ") + name + " frozen in " + std::to_string(n) + " frames";
    }
    if (!cameras.empty()) {
      out += std::string(out.empty() ? "" : "\n") + "cameras left out: " + cameras;
    }
  }
  return out;
}

}  // namespace parkslam::harness
