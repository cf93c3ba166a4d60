// The live API (live/live_system.h) as a car runs it: a simulated drive of
// the default lot replayed event by event at its own pace (or --speed times
// it), the camera frames rendered on the fly at --rate-hz, localized on the
// lot's map from the true start. Prints the frames received, perceived and
// dropped, the latency from each frame's arrival to its first pose (its
// slots') and to its second (its tags' too), median, 99th percentile and
// max, and the pose error against the truth.
//
//   parkslam_live_bench [--seconds 60] [--speed 1] [--rate-hz 5] [--no-images]
//                       [--global-start] [--seed 501]
//                       [--system-core N --camera-core M] [--band-tags]
//
// Seed 501 is the demo's second drive (the one it localizes); the start is
// the true one unless --global-start (the demo's).
//
// On one core: taskset -c 0 parkslam_live_bench (the renderer then shares
// the core with the perception; a car's cameras do not). --system-core N
// --camera-core M: the live system (its perception thread too) on core N,
// the renderer that stands in for the cameras, and the replay, on core M.
// --band-tags: the tags looked for in the whole band at every frame, not in
// windows around the map's tags (perception::TagWindowOptions off).

#include <sched.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "parkslam/common/percentile.h"
#include "parkslam/harness/live_cameras.h"
#include "parkslam/harness/rendering_source.h"
#include "parkslam/live/live_system.h"
#include "parkslam/odometry/odometry_ekf.h"
#include "parkslam/perception/front_end.h"
#include "parkslam/sensor/sensor_log.h"
#include "parkslam/sim/simulator.h"

namespace {

using namespace parkslam;

struct BenchOptions {
  double seconds = 60.0;
  double speed = 1.0;
  double rate_hz = 5.0;
  bool images = true;
  bool global_start = false;
  std::uint64_t seed = 501;  // the demo's second drive
  int system_core = -1, camera_core = -1;
  bool band_tags = false;
};

// Pins the calling thread (and the threads it starts later) to one core.
bool PinTo(int core) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(core, &set);
  return sched_setaffinity(0, sizeof(set), &set) == 0;
}

int ParseArgs(int argc, char** argv, BenchOptions* o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--seconds" && i + 1 < argc) {
      o->seconds = std::atof(argv[++i]);
    } else if (a == "--speed" && i + 1 < argc) {
      o->speed = std::atof(argv[++i]);
    } else if (a == "--rate-hz" && i + 1 < argc) {
      o->rate_hz = std::atof(argv[++i]);
    } else if (a == "--seed" && i + 1 < argc) {
      o->seed = std::strtoull(argv[++i], nullptr, 10);
    } else if (a == "--no-images") {
      o->images = false;
    } else if (a == "--band-tags") {
      o->band_tags = true;
    } else if (a == "--global-start") {
      o->global_start = true;
    } else if (a == "--system-core" && i + 1 < argc) {
      o->system_core = std::atoi(argv[++i]);
    } else if (a == "--camera-core" && i + 1 < argc) {
      o->camera_core = std::atoi(argv[++i]);
    } else {
      std::fprintf(stderr,
                   "usage: parkslam_live_bench [--seconds 60] [--speed 1] [--rate-hz 5] "
                   "[--no-images] [--global-start] [--seed 501] [--system-core N "
                   "--camera-core M] [--band-tags]\n");
      return a == "--help" || a == "-h" ? 0 : 2;
    }
  }
  if (!(o->seconds >= 1.0 && o->seconds <= 3600.0) || !(o->speed > 0.0 && o->speed <= 100.0) ||
      !(o->rate_hz > 0.0 && o->rate_hz <= 30.0)) {
    std::fprintf(stderr,
                 "parkslam_live_bench: --seconds in [1, 3600], --speed in (0, 100], --rate-hz in "
                 "(0, 30]\n");
    return 2;
  }
  return -1;
}

}  // namespace

int main(int argc, char** argv) {
  BenchOptions o;
  if (const int code = ParseArgs(argc, argv, &o); code >= 0) return code;
  const sim::ScenarioConfig scenario = sim::DefaultScenario();
  const sim::Simulation drive = sim::Simulate(scenario, o.seed);
  const Trajectory truth = sim::GroundTruthTrajectory(drive);
  const SemanticMap map = sim::ToSemanticMap(drive.world);
  live::LiveOptions options;
  options.odometry = odometry::EkfOptionsFromSpec(scenario.sensors.odometry, scenario.vehicle);
  options.perception.tag_windows.enabled = !o.band_tags;

  std::optional<harness::LiveCameras> cameras;
  SensorLogSource log(drive.log);
  std::optional<harness::RenderingSource> rendered;
  SensorSource* source = &log;
  if (o.images) {
    cameras.emplace(sim::BuildWorld(scenario.world), scenario.world, o.seed, options.perception);
    rendered.emplace(log, cameras->renderer(), truth, cameras->cameras(), o.rate_hz);
    source = &*rendered;
  }
  std::optional<SE2> start;
  if (!o.global_start) start = truth.front().T_map_vehicle;
  // The live system's perception thread takes the affinity its creator has.
  if (o.system_core >= 0 && !PinTo(o.system_core)) {
    std::fprintf(stderr, "parkslam_live_bench: cannot pin to core %d\n", o.system_core);
    return 2;
  }
  live::LiveSystem live(map, o.images ? &cameras->rig() : nullptr, options, start);
  if (o.camera_core >= 0 && !PinTo(o.camera_core)) {
    std::fprintf(stderr, "parkslam_live_bench: cannot pin to core %d\n", o.camera_core);
    return 2;
  }

  using Clock = std::chrono::steady_clock;
  const TimeNs t0_ns = truth.front().t_ns;
  const TimeNs end_ns = t0_ns + FromSeconds(o.seconds);
  const Clock::time_point wall0 = Clock::now();
  double sum_sq = 0.0, worst_m = 0.0;
  int estimates = 0;
  std::vector<localization::LocalizationEstimate> all;
  auto score = [&](const std::vector<localization::LocalizationEstimate>& taken) {
    for (const auto& e : taken) {
      all.push_back(e);
      const std::optional<SE2> at = PoseAt(truth, e.t_ns);
      if (!at) continue;
      const double error_m = (e.T_map_vehicle.translation() - at->translation()).norm();
      sum_sq += error_m * error_m;
      worst_m = std::max(worst_m, error_m);
      ++estimates;
    }
  };
  while (const auto event = source->Next()) {
    const TimeNs t_ns = EventTime(*event);
    if (t_ns > end_ns) break;
    // On pixels a car has no slot or tag frames but what its cameras see.
    if (o.images && (std::holds_alternative<SlotObservationFrame>(*event) ||
                     std::holds_alternative<TagObservationFrame>(*event))) {
      continue;
    }
    std::this_thread::sleep_until(wall0 + std::chrono::nanoseconds(static_cast<std::int64_t>(
                                              static_cast<double>(t_ns - t0_ns) / o.speed)));
    live.Process(*event);
    score(live.TakeEstimates());
  }
  live.Finish();
  score(live.TakeEstimates());
  // The same drive through `localize`'s chain (the perception in the same
  // thread, event by event), as fast as it goes: the poses the live API
  // must give.
  SensorLogSource log_again(drive.log);
  std::optional<harness::RenderingSource> rendered_again;
  std::optional<perception::PerceptionSource> perceived;
  SensorSource* reference_source = &log_again;
  if (o.images) {
    rendered_again.emplace(log_again, cameras->renderer(), truth, cameras->cameras(), o.rate_hz);
    perceived.emplace(*rendered_again, cameras->front_end());
    reference_source = &*perceived;
  }
  localization::Localizer reference(map, options.localizer, options.odometry);
  if (start) reference.SetPose(*start, Eigen::Vector3d(0.5, 0.5, 0.1).cwiseAbs2().asDiagonal());
  if (perceived) {
    perceived->SearchTagsIn(
        [&](TimeNs t_ns) { return live::MapTagWindows(cameras->front_end(), reference, t_ns); });
  }
  size_t compared = 0;
  double most_apart_m = 0.0;
  bool same_times = true;
  while (const auto event = reference_source->Next()) {
    if (EventTime(*event) > end_ns) break;
    if (const auto e = reference.Process(*event)) {
      if (compared >= all.size() || all[compared].t_ns != e->t_ns) {
        same_times = false;
        break;
      }
      most_apart_m = std::max(
          most_apart_m,
          (all[compared].T_map_vehicle.translation() - e->T_map_vehicle.translation()).norm());
      ++compared;
    }
  }
  const live::LiveStats st = live.stats();
  std::printf(
      "%.0f s of drive at %.1fx, %s: %d camera frames, %d perceived (tags in windows at %d), "
      "%d dropped; %d estimates; "
      "latency to the frame's first pose median %.2f ms, p99 %.2f ms, max %.2f ms; with its "
      "tags median %.2f ms, p99 %.2f ms (perception median %.2f ms, p99 %.2f ms); pose RMSE "
      "%.3f m, worst %.3f m\n",
      o.seconds, o.speed, o.images ? "on pixels" : "on slot and tag frames", st.camera_frames,
      st.frames_perceived, st.tag_searches_in_windows, st.frames_dropped, estimates,
      Percentile(st.latency_ms, 0.5), Percentile(st.latency_ms, 0.99),
      Percentile(st.latency_ms, 1.0), Percentile(st.complete_latency_ms, 0.5),
      Percentile(st.complete_latency_ms, 0.99), Percentile(st.perception_ms, 0.5),
      Percentile(st.perception_ms, 0.99), estimates > 0 ? std::sqrt(sum_sq / estimates) : 0.0,
      worst_m);
  std::printf("against localize's chain: %s, %zu of %zu poses compared, at most %.2e m apart\n",
              same_times && compared == all.size() ? "the same frames" : "NOT the same frames",
              compared, all.size(), most_apart_m);
  return 0;
}
