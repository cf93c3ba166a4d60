// Soak: a long simulated drive, mapped and then localized, with the memory
// of the process and the time of each update sampled every minute of drive
// (docs/robustness.md, "Soak").
//
//   parkslam_soak_bench [--minutes 60] [--seed 3] [--mode batch|online] [--out DIR]
//
// Simulates the default lot for about `minutes` of driving (laps of the
// default route), maps it at observation level, then localizes a second
// drive of the same length (seed + 1) on the map. --mode online maps as a
// car would live (docs/mapping.md, "Online at batch accuracy"): a windowed
// update per keyframe and the full solve in the background. Prints one line per
// minute and a summary: resident memory (MB) at the start and end of each
// phase and its growth per hour, and the median and 99th percentile of the
// per-keyframe (mapping) and per-frame (localization) update times in the
// first and last ten minutes. With --out it writes soak.csv and soak.svg
// there. The simulated logs are held in memory from the start, so growth
// during a phase is the mapper's or the localizer's.

#include <unistd.h>

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "parkslam/common/percentile.h"
#include "parkslam/eval/map_metrics.h"
#include "parkslam/harness/dead_reckoning.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/localization/localizer.h"
#include "parkslam/mapping/mapper.h"
#include "parkslam/sim/scenario_config.h"
#include "parkslam/sim/simulator.h"
#include "parkslam/viz/svg.h"

namespace {

using namespace parkslam;

double ResidentMb() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return static_cast<double>(resident) * static_cast<double>(::sysconf(_SC_PAGESIZE)) / 1e6;
}

// The heap in use (glibc's count of allocated bytes): what the program
// holds, apart from what the allocator keeps of freed blocks for reuse,
// which the resident size also counts and seldom gives back.
double HeapInUseMb() {
  const struct mallinfo2 info = ::mallinfo2();
  return static_cast<double>(info.uordblks + info.hblkhd) / 1e6;
}

// One minute of drive in one phase.
struct Minute {
  std::string phase;
  int minute = 0;
  double resident_mb = 0.0;
  double heap_mb = 0.0;
  int updates = 0;  // keyframes or localized frames
  double median_ms = 0.0, p99_ms = 0.0, max_ms = 0.0;
};

Minute Summarize(const std::string& phase, int minute, const std::vector<double>& ms) {
  Minute m;
  m.phase = phase;
  m.minute = minute;
  m.resident_mb = ResidentMb();
  m.heap_mb = HeapInUseMb();
  m.updates = static_cast<int>(ms.size());
  m.median_ms = Percentile(ms, 0.5);
  m.p99_ms = Percentile(ms, 0.99);
  m.max_ms = ms.empty() ? 0.0 : *std::max_element(ms.begin(), ms.end());
  return m;
}

void PrintMinute(const Minute& m) {
  std::printf(
      "%-9s min %3d  %8.1f MB (heap %7.1f MB)  %6d updates  median %.3f ms  p99 %.3f ms  max %.2f "
      "ms\n",
      m.phase.c_str(), m.minute, m.resident_mb, m.heap_mb, m.updates, m.median_ms, m.p99_ms,
      m.max_ms);
}

// Median and p99 over minutes [from, to) of a phase.
std::pair<double, double> Window(const std::vector<Minute>& minutes, const std::string& phase,
                                 int from, int to) {
  std::vector<double> medians, p99s;
  for (const Minute& m : minutes) {
    if (m.phase == phase && m.minute >= from && m.minute < to && m.updates > 0) {
      medians.push_back(m.median_ms);
      p99s.push_back(m.p99_ms);
    }
  }
  return {Percentile(medians, 0.5), Percentile(p99s, 0.5)};
}

// Two panels over drive minutes: resident memory, and update times.
std::string Plot(const std::vector<Minute>& minutes, int total_minutes) {
  const double w = 720, h = 250, left = 60, gap = 40;
  viz::SvgCanvas canvas(Eigen::Vector2d(0, 0), Eigen::Vector2d(w, 2 * h + gap), 1.0, 10.0);
  const auto panel = [&](double y0, const char* title, auto value, double top,
                         const std::vector<std::pair<std::string, std::string>>& series) {
    const auto at = [&](double minute, double v) {
      return Eigen::Vector2d(left + (w - left - 10) * minute / std::max(1, total_minutes),
                             y0 + 20 + (h - 50) * std::clamp(v / top, 0.0, 1.0));
    };
    viz::SvgStyle axis;
    axis.stroke = "#444";
    axis.width_px = 1;
    canvas.Polyline({at(0, top), at(0, 0), at(total_minutes, 0)}, axis);
    viz::SvgStyle label;
    label.font_size_px = 12;
    label.fill = "#222";
    canvas.Text(Eigen::Vector2d(left, y0 + h - 10), title, label);
    canvas.Text(at(0, top) + Eigen::Vector2d(-55, 0), viz::FormatFixed(top, 2), label);
    canvas.Text(at(0, 0) + Eigen::Vector2d(-20, 0), "0", label);
    canvas.Text(at(total_minutes, 0) + Eigen::Vector2d(-60, -15),
                std::to_string(total_minutes) + " min", label);
    double legend_y = top;
    for (const auto& [phase_key, colour] : series) {
      std::vector<Eigen::Vector2d> points;
      for (const Minute& m : minutes) {
        if (m.phase + value.name_suffix(m) == phase_key && !value.skip(m)) {
          points.push_back(at(m.minute, value(m)));
        }
      }
      viz::SvgStyle line;
      line.stroke = colour;
      line.width_px = 1.5;
      canvas.Polyline(points, line);
      viz::SvgStyle text = label;
      text.fill = colour;
      canvas.Text(at(total_minutes * 0.02, legend_y) + Eigen::Vector2d(10, -14), phase_key, text);
      legend_y -= top * 0.09;
    }
  };
  struct Memory {
    std::string name_suffix(const Minute&) const { return ""; }
    bool skip(const Minute&) const { return false; }
    double operator()(const Minute& m) const { return m.resident_mb; }
  };
  double top_mb = 0.0, top_ms = 0.0;
  for (const Minute& m : minutes) {
    top_mb = std::max(top_mb, m.resident_mb);
    top_ms = std::max(top_ms, m.p99_ms);
  }
  panel(h + gap, "resident memory (MB) over drive minutes", Memory{}, 1.1 * top_mb,
        {{"mapping", "#1f77b4"}, {"localizing", "#d62728"}});
  // The update-time panel draws the p99 of each phase.
  struct P99 {
    std::string name_suffix(const Minute&) const { return " p99"; }
    bool skip(const Minute& m) const { return m.updates == 0; }  // minute 0: nothing yet
    double operator()(const Minute& m) const { return m.p99_ms; }
  };
  panel(0, "update time (ms), 99th percentile per minute", P99{}, 1.1 * top_ms,
        {{"mapping p99", "#1f77b4"}, {"localizing p99", "#d62728"}});
  return canvas.Finish();
}

struct SoakOptions {
  double minutes = 60.0;
  std::uint64_t seed = 3;
  std::string out;
  bool online = false;
};

// The command line into o; an exit code when the program should stop,
// -1 otherwise.
int ParseArgs(int argc, char** argv, SoakOptions* o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--minutes" && i + 1 < argc) {
      o->minutes = std::atof(argv[++i]);
    } else if (a == "--seed" && i + 1 < argc) {
      o->seed = std::strtoull(argv[++i], nullptr, 10);
    } else if (a == "--out" && i + 1 < argc) {
      o->out = argv[++i];
    } else if (a == "--mode" && i + 1 < argc &&
               (std::string(argv[i + 1]) == "online" || std::string(argv[i + 1]) == "batch")) {
      o->online = std::string(argv[++i]) == "online";
    } else {
      std::fprintf(stderr,
                   "usage: parkslam_soak_bench [--minutes 60] [--seed 3] [--mode batch|online] "
                   "[--out DIR]\n");
      return a == "--help" || a == "-h" ? 0 : 2;
    }
  }
  if (!(o->minutes >= 3.0 && o->minutes <= 600.0)) {
    std::fprintf(stderr, "parkslam_soak_bench: --minutes must lie in [3, 600]\n");
    return 2;
  }
  return -1;
}

// Maps the drive, a row of the table per minute of drive.
void MapDrive(const SensorLog& log, TimeNs start_ns, mapping::Mapper* mapper,
              std::vector<Minute>* table) {
  SensorLogSource source(log);
  int minute = 0;
  std::size_t first_keyframe = 0;
  table->push_back(Summarize("mapping", 0, {}));
  PrintMinute(table->back());
  while (const auto event = source.Next()) {
    mapper->Process(*event);
    const int now = static_cast<int>(ToSeconds(EventTime(*event) - start_ns) / 60.0);
    if (now > minute) {
      const std::vector<double>& ms = mapper->stats().keyframe_update_ms;
      table->push_back(
          Summarize("mapping", now,
                    std::vector<double>(ms.begin() + static_cast<long>(first_keyframe), ms.end())));
      PrintMinute(table->back());
      first_keyframe = ms.size();
      minute = now;
    }
  }
  const auto f0 = std::chrono::steady_clock::now();
  mapper->Finish();
  std::printf("final solve %.1f s; %.1f MB resident\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - f0).count(),
              ResidentMb());
}

// Localizes the drive on the map, a row of the table per minute of drive.
void LocalizeDrive(const SemanticMap& map, const SensorLog& log,
                   const odometry::OdometryEkfOptions& ekf, TimeNs start_ns,
                   std::vector<Minute>* table) {
  localization::Localizer localizer(map, localization::LocalizerOptions{}, ekf);
  SensorLogSource source(log);
  int minute = 0;
  std::vector<double> ms;
  table->push_back(Summarize("localizing", 0, {}));
  PrintMinute(table->back());
  while (const auto event = source.Next()) {
    const auto s = std::chrono::steady_clock::now();
    const bool estimated = localizer.Process(*event).has_value();
    if (estimated) {
      ms.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - s).count());
    }
    const int now = static_cast<int>(ToSeconds(EventTime(*event) - start_ns) / 60.0);
    if (now > minute) {
      table->push_back(Summarize("localizing", now, ms));
      PrintMinute(table->back());
      ms.clear();
      minute = now;
    }
  }
}

// Memory growth and update times, first against last ten minutes.
void PrintSummary(const std::vector<Minute>& table, double drive_min) {
  const int last = static_cast<int>(drive_min);
  std::printf("\nsummary over %d minutes of drive per phase:\n", last);
  for (const char* phase : {"mapping", "localizing"}) {
    double first_mb = 0.0, last_mb = 0.0, first_heap = 0.0, last_heap = 0.0;
    bool seen = false;
    for (const Minute& m : table) {
      if (m.phase != phase) continue;
      if (!seen) first_mb = m.resident_mb, first_heap = m.heap_mb;
      seen = true;
      last_mb = m.resident_mb;
      last_heap = m.heap_mb;
    }
    const auto early = Window(table, phase, 1, 11);
    const auto late = Window(table, phase, last - 10, last + 1);
    std::printf(
        "%-10s memory %.1f -> %.1f MB (%+.1f MB per hour of drive), heap in use %.1f -> %.1f MB; "
        "update median %.3f -> %.3f ms, p99 %.3f -> %.3f ms (first vs last ten minutes)\n",
        phase, first_mb, last_mb, (last_mb - first_mb) / std::max(drive_min, 1.0) * 60.0,
        first_heap, last_heap, early.first, late.first, early.second, late.second);
  }
}

void WriteTable(const std::string& out, const std::vector<Minute>& table, int last) {
  std::filesystem::create_directories(out);
  std::string csv = "phase,minute,resident_mb,heap_mb,updates,median_ms,p99_ms,max_ms\n";
  for (const Minute& m : table) {
    char line[160];
    std::snprintf(line, sizeof line, "%s,%d,%.2f,%.2f,%d,%.4f,%.4f,%.3f\n", m.phase.c_str(),
                  m.minute, m.resident_mb, m.heap_mb, m.updates, m.median_ms, m.p99_ms, m.max_ms);
    csv += line;
  }
  io::WriteFileAtomically(std::filesystem::path(out) / "soak.csv", csv);
  io::WriteFileAtomically(std::filesystem::path(out) / "soak.svg", Plot(table, last));
  std::printf("wrote %s/soak.csv and soak.svg\n", out.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  SoakOptions options;
  if (const int code = ParseArgs(argc, argv, &options); code >= 0) return code;
  // The default route: about 120 s before the laps, 103 s a lap.
  sim::ScenarioConfig scenario = sim::DefaultScenario();
  scenario.route.laps =
      std::max(1, static_cast<int>(std::lround((options.minutes * 60.0 - 120.0) / 103.3)));
  const auto t0 = std::chrono::steady_clock::now();
  const sim::Simulation drive = sim::Simulate(scenario, options.seed);
  const sim::Simulation second = sim::Simulate(scenario, options.seed + 1);
  const SemanticMap truth = sim::ToSemanticMap(drive.world);
  const odometry::OdometryEkfOptions ekf =
      odometry::EkfOptionsFromSpec(scenario.sensors.odometry, scenario.vehicle);
  const TimeNs start_ns = drive.states.front().t_ns;
  const double drive_min = ToSeconds(drive.states.back().t_ns - start_ns) / 60.0;
  std::printf("%d laps, %.1f min of drive each; simulated in %.1f s; %.1f MB resident\n",
              scenario.route.laps, drive_min,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
              ResidentMb());

  std::vector<Minute> table;
  mapping::MapperOptions mapper_options;
  if (options.online) mapper_options.mode = mapping::MappingMode::kOnline;
  mapping::Mapper mapper(mapper_options, ekf);
  MapDrive(drive.log, start_ns, &mapper, &table);
  const SemanticMap map = mapper.Map();
  const eval::MapMetrics metrics = eval::EvaluateMap(map, truth);
  std::printf("map: %d of %d slots, corner RMSE %.3f m; %d keyframes\n", metrics.slots_matched,
              metrics.slots_true, metrics.slot_corner_rmse_m, mapper.stats().keyframes);
  if (const mapping::MapperStats& st = mapper.stats(); st.background_solves > 0) {
    std::printf("%d background solves, median %.0f ms, p99 %.0f ms, max %.0f ms\n",
                st.background_solves, Percentile(st.background_solve_ms, 0.5),
                Percentile(st.background_solve_ms, 0.99), Percentile(st.background_solve_ms, 1.0));
  }

  // Localization of the second drive.
  LocalizeDrive(map, second.log, ekf, start_ns, &table);
  PrintSummary(table, drive_min);
  if (!options.out.empty()) WriteTable(options.out, table, static_cast<int>(drive_min));
  return 0;
}
