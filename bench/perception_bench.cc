// Perception per camera frame set, stage by stage, on one core (goal: the
// four stages together at most 20 ms), with the classical and the learned
// slot detector and ID reader (docs/learned_perception.md). The frame is
// rendered once in the default lot, in aisle 1 between two rows of slots,
// with tags in view of the front camera.

#include <benchmark/benchmark.h>

#include "parkslam/camera/camera_model.h"
#include "parkslam/camera/image_plane.h"
#include "parkslam/harness/live_cameras.h"
#include "parkslam/perception/front_end.h"
#include "parkslam/sim/scenario_config.h"

namespace parkslam {
namespace {

struct Fixture {
  camera::CameraRig rig = camera::DefaultRig();
  perception::PerceptionFrontEnd front_end{rig, ClassicalOptions()};
  perception::PerceptionFrontEnd learned_front_end{rig, LearnedOptions()};
  perception::PerceptionFrontEnd network_ids_front_end{rig, LearnedOptions(false)};
  perception::LearnedSlotDetector learned_detector{learned_front_end.options().learned_slots};
  perception::LearnedSlotIdReader learned_reader{learned_front_end.options().learned_ids};
  perception::SlotDetector detector{front_end.options().slots};
  perception::SlotIdReader reader{front_end.options().ids};
  perception::TagDetector tags{front_end.options().tags};
  CameraFrame frame;
  std::vector<cv::Mat> fisheyes;
  cv::Mat front_mono, top_view;
  perception::SlotDetection detection;

  static perception::PerceptionOptions ClassicalOptions() {
    perception::PerceptionOptions o;
    o.detector = perception::DetectorKind::kClassical;
    return o;
  }
  // The learned front end (the default); the classical reader reads the IDs it is sure
  // of first unless !classical_ids (then the network reads every ID, as in
  // a lot whose IDs are painted in another face).
  static perception::PerceptionOptions LearnedOptions(bool classical_ids = true) {
    perception::PerceptionOptions o;
    o.detector = perception::DetectorKind::kLearned;
    o.learned_ids_with_classical = classical_ids;
    return o;
  }

  Fixture() {
    const harness::LiveCameras cameras(sim::BuildWorld(sim::DefaultScenario().world), 1);
    // Aisle 1, near the tags of the hall's west part.
    frame = cameras.Render(SE2(12.0, 9.1, 0.0), 0);
    for (size_t k = 0; k < 5; ++k) {
      const cv::Mat m = camera::AsMat(frame.images[k]);
      if (k < 4) {
        fisheyes.push_back(m);
      } else {
        front_mono = m;
      }
    }
    top_view = front_end.fusion().Fuse(fisheyes);
    detection = detector.Detect(top_view, front_end.FootprintMask());
  }
};

const Fixture& Get() {
  static const Fixture f;
  return f;
}

void BM_PerceptionFuseTopView(benchmark::State& state) {
  const Fixture& f = Get();
  for (auto _ : state) benchmark::DoNotOptimize(f.front_end.fusion().Fuse(f.fisheyes).data);
}
BENCHMARK(BM_PerceptionFuseTopView)->Unit(benchmark::kMillisecond);

void BM_PerceptionDetectSlots(benchmark::State& state) {
  const Fixture& f = Get();
  for (auto _ : state) {
    const perception::SlotDetection d = f.detector.Detect(f.top_view, f.front_end.FootprintMask());
    benchmark::DoNotOptimize(d.slots.size());
  }
  state.counters["slots"] = static_cast<double>(f.detection.slots.size());
}
BENCHMARK(BM_PerceptionDetectSlots)->Unit(benchmark::kMillisecond);

void BM_PerceptionReadIds(benchmark::State& state) {
  const Fixture& f = Get();
  for (auto _ : state) {
    for (const perception::DetectedSlot& s : f.detection.slots) {
      benchmark::DoNotOptimize(
          f.reader.Read(f.top_view, {s.corners_px[0], s.corners_px[1], s.depth_dir_px})
              .digits.size());
    }
  }
}
BENCHMARK(BM_PerceptionReadIds)->Unit(benchmark::kMillisecond);

// The marking-point network alone (resize and inference), then the learned
// detector as the front end runs it (with the classical check it is set to).
void BM_PerceptionMarkingPointNetwork(benchmark::State& state) {
  const Fixture& f = Get();
  for (auto _ : state) benchmark::DoNotOptimize(f.learned_detector.Cells(f.top_view).data);
  state.counters["input_px"] = f.learned_detector.options().input_size_px;
}
BENCHMARK(BM_PerceptionMarkingPointNetwork)->Unit(benchmark::kMillisecond);

void BM_PerceptionDetectSlotsLearned(benchmark::State& state) {
  const Fixture& f = Get();
  for (auto _ : state) {
    const perception::SlotDetection d =
        f.learned_detector.Detect(f.top_view, f.front_end.FootprintMask());
    benchmark::DoNotOptimize(d.slots.size());
  }
}
BENCHMARK(BM_PerceptionDetectSlotsLearned)->Unit(benchmark::kMillisecond);

void BM_PerceptionReadIdsLearned(benchmark::State& state) {
  const Fixture& f = Get();
  for (auto _ : state) {
    for (const perception::DetectedSlot& s : f.detection.slots) {
      benchmark::DoNotOptimize(
          f.learned_reader.Read(f.top_view, {s.corners_px[0], s.corners_px[1], s.depth_dir_px})
              .digits.size());
    }
  }
  state.counters["slots"] = static_cast<double>(f.detection.slots.size());
}
BENCHMARK(BM_PerceptionReadIdsLearned)->Unit(benchmark::kMillisecond);

// The whole 1280x720 image, for comparison with the band the front end
// searches.
void BM_PerceptionDetectTagsFullImage(benchmark::State& state) {
  const Fixture& f = Get();
  const camera::CameraIntrinsics& k = f.rig.cameras.back().intrinsics;
  for (auto _ : state) benchmark::DoNotOptimize(f.tags.Detect(f.front_mono, &k).size());
}
BENCHMARK(BM_PerceptionDetectTagsFullImage)->Unit(benchmark::kMillisecond);

// Everything the front end does with one frame set: fusion, slots, IDs,
// tags (in the band), and the observations.
void BM_PerceptionFrame(benchmark::State& state) {
  const Fixture& f = Get();
  double tags_ms = 0.0;
  for (auto _ : state) {
    const perception::PerceptionOutput out = f.front_end.Process(f.frame);
    tags_ms = out.timing.tags_ms;
    benchmark::DoNotOptimize(out.slots.slots.size());
  }
  state.counters["tags_ms"] = tags_ms;
}
BENCHMARK(BM_PerceptionFrame)->Unit(benchmark::kMillisecond);

void RunLearnedFrame(benchmark::State& state, const perception::PerceptionFrontEnd& front_end) {
  const Fixture& f = Get();
  double tags_ms = 0.0, slots_ms = 0.0, ids_ms = 0.0;
  for (auto _ : state) {
    const perception::PerceptionOutput out = front_end.Process(f.frame);
    tags_ms = out.timing.tags_ms;
    slots_ms = out.timing.slots_ms;
    ids_ms = out.timing.ids_ms;
    benchmark::DoNotOptimize(out.slots.slots.size());
  }
  state.counters["tags_ms"] = tags_ms;
  state.counters["slots_ms"] = slots_ms;
  state.counters["ids_ms"] = ids_ms;
}

void BM_PerceptionFrameLearned(benchmark::State& state) {
  RunLearnedFrame(state, Get().learned_front_end);
}
BENCHMARK(BM_PerceptionFrameLearned)->Unit(benchmark::kMillisecond);

// Every ID read by the network.
void BM_PerceptionFrameLearnedNetworkIds(benchmark::State& state) {
  RunLearnedFrame(state, Get().network_ids_front_end);
}
BENCHMARK(BM_PerceptionFrameLearnedNetworkIds)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace parkslam
