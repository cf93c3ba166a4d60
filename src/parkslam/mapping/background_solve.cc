#include "parkslam/mapping/background_solve.h"

#include <pthread.h>
#include <sched.h>

#include <chrono>
#include <utility>

namespace parkslam::mapping {
namespace {

// Appends to `to` the elements of `from` beyond its size.
template <typename Container>
void AppendNew(const Container& from, Container* to) {
  to->insert(to->end(), from.begin() + static_cast<std::ptrdiff_t>(to->size()), from.end());
}

}  // namespace

BackgroundSolve::~BackgroundSolve() {
  if (thread_.joinable()) thread_.join();
}

void BackgroundSolve::Mirror(const MapState& state, bool rebuild) {
  MapState& m = mirror_;
  m.wheel_scale_error = state.wheel_scale_error;
  m.wheel_scale_sigma = state.wheel_scale_sigma;
  const bool shrank = m.keyframes.size() > state.keyframes.size() ||
                      m.slots.size() > state.slots.size() || m.tags.size() > state.tags.size() ||
                      m.slot_records.size() > state.slot_records.size() ||
                      m.tag_records.size() > state.tag_records.size();
  if (rebuild || shrank) {
    m.keyframes = state.keyframes;
    m.slots = state.slots;
    m.tags = state.tags;
    m.slot_records = state.slot_records;
    m.tag_records = state.tag_records;
    return;
  }
  // Between structure changes the state only grows, and of what it has
  // only the values move: the keyframes' poses, the slots' corners (and
  // whether they live), the tags' poses, the records' choices.
  for (size_t k = 0; k < m.keyframes.size(); ++k) m.keyframes[k].pose = state.keyframes[k].pose;
  AppendNew(state.keyframes, &m.keyframes);
  for (size_t s = 0; s < m.slots.size(); ++s) {
    m.slots[s].corners = state.slots[s].corners;
    m.slots[s].alive = state.slots[s].alive;
  }
  AppendNew(state.slots, &m.slots);
  m.tags = state.tags;
  for (size_t r = 0; r < m.slot_records.size(); ++r) {
    m.slot_records[r].chosen = state.slot_records[r].chosen;
  }
  AppendNew(state.slot_records, &m.slot_records);
  AppendNew(state.tag_records, &m.tag_records);
}

void BackgroundSolve::Start(const MapState& state, bool rebuild, int max_iterations,
                            const MapperOptions& options) {
  if (thread_.joinable()) Wait();
  Mirror(state, rebuild);
  finished_ = false;
  error_ = nullptr;
  thread_ = std::thread([this, max_iterations, options] {
    // Idle priority: the foreground (the next keyframe's update) always
    // goes first; the full solve takes what the car's cycle leaves over.
    sched_param param{};
    pthread_setschedparam(pthread_self(), SCHED_IDLE, &param);
    const auto start = std::chrono::steady_clock::now();
    try {
      result_ = SolveMapGraph(&mirror_, 0, max_iterations, true, options);
    } catch (...) {
      error_ = std::current_exception();
    }
    solve_ms_ =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    finished_ = true;
  });
}

bool BackgroundSolve::done() const { return thread_.joinable() && finished_.load(); }

MapGraphSolve BackgroundSolve::Wait() {
  if (thread_.joinable()) thread_.join();
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  return std::move(result_);
}

}  // namespace parkslam::mapping
