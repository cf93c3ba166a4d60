#ifndef PARKSLAM_MAPPING_BACKGROUND_SOLVE_H_
#define PARKSLAM_MAPPING_BACKGROUND_SOLVE_H_

// The full solve of the mapper's graph in a background thread, for online
// mapping at batch accuracy (docs/mapping.md, "Online at batch accuracy").
// The windowed solves that run in the foreground after every keyframe never
// revisit the keyframes before their window; this one solves every
// keyframe, slot and tag, on a mirror of the map state, while the car
// drives on. The mapper then lays its solution into the state
// (Mapper::ApplyBackgroundSolve), moving what was added meanwhile with the
// correction of the newest keyframe it knew.
//
// The mirror is kept in step with the state by appending what is new and
// copying the values (poses, corners, choices) of what it has, so that
// starting a solve costs the foreground the new records, not the whole
// drive; the state's structure changes (records retired, keyframes culled,
// slots merged or pruned) rebuild it whole.

#include <atomic>
#include <cstddef>
#include <exception>
#include <thread>

#include "parkslam/mapping/map_graph.h"
#include "parkslam/mapping/map_state.h"
#include "parkslam/mapping/mapper_options.h"

namespace parkslam::mapping {

class BackgroundSolve {
 public:
  BackgroundSolve() = default;
  ~BackgroundSolve();
  BackgroundSolve(const BackgroundSolve&) = delete;
  BackgroundSolve& operator=(const BackgroundSolve&) = delete;

  // Brings the mirror in step with `state` (whole when `rebuild`, or when
  // the state shrank since), then solves it in a thread of idle priority:
  // all keyframes free but the first, every record, at most max_iterations.
  // Not while one runs.
  void Start(const MapState& state, bool rebuild, int max_iterations, const MapperOptions& options);
  bool running() const { return thread_.joinable(); }
  // Whether the running solve has finished (then Wait does not block).
  bool done() const;
  // Waits for the solve; rethrows what it threw. The solution is then in
  // solved(), and its sizes at the start below.
  MapGraphSolve Wait();

  const MapState& solved() const { return mirror_; }
  // What the state held when the solve started: its first keyframes,
  // slots, tags and records are the mirror's.
  size_t keyframes() const { return mirror_.keyframes.size(); }
  size_t slots() const { return mirror_.slots.size(); }
  size_t tags() const { return mirror_.tags.size(); }
  size_t slot_records() const { return mirror_.slot_records.size(); }
  // Wall time of the last finished solve in its thread.
  double last_solve_ms() const { return solve_ms_; }

 private:
  void Mirror(const MapState& state, bool rebuild);

  MapState mirror_;
  std::thread thread_;
  std::atomic<bool> finished_{false};
  MapGraphSolve result_;
  std::exception_ptr error_;
  double solve_ms_ = 0.0;
};

}  // namespace parkslam::mapping

#endif  // PARKSLAM_MAPPING_BACKGROUND_SOLVE_H_
