#include "parkslam/live/live_system.h"

#include <algorithm>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <utility>

namespace parkslam::live {
namespace {

bool IsOdometry(const SensorEvent& event) {
  return std::holds_alternative<WheelSpeed>(event) ||
         std::holds_alternative<SteeringAngle>(event) || std::holds_alternative<ImuSample>(event);
}

double MsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace

std::optional<std::vector<perception::TagWindow>> MapTagWindows(
    const perception::PerceptionFrontEnd& front_end, const localization::Localizer& localizer,
    TimeNs t_ns) {
  const auto tracked = localizer.TrackedAt(t_ns);
  if (!tracked) return std::nullopt;
  return front_end.TagWindows(localizer.map().tags, tracked->first, tracked->second);
}

LiveSystem::LiveSystem(Common, const camera::CameraRig* rig, const LiveOptions& options)
    : options_(options), rig_(rig), ahead_(options.odometry) {}

LiveSystem::LiveSystem(const SemanticMap& map, const camera::CameraRig* rig,
                       const LiveOptions& options, std::optional<SE2> initial_pose,
                       const Eigen::Vector3d& initial_sigma)
    : LiveSystem(Common{}, rig, options) {
  map_ = map;
  localizer_ =
      std::make_unique<localization::Localizer>(map_, options_.localizer, options_.odometry);
  if (initial_pose) localizer_->SetPose(*initial_pose, initial_sigma.cwiseAbs2().asDiagonal());
  StartPerception();
}

LiveSystem::LiveSystem(const camera::CameraRig* rig, const LiveOptions& options,
                       std::optional<SE2> initial_pose)
    : LiveSystem(Common{}, rig, options) {
  options_.mapper.mode = mapping::MappingMode::kOnline;
  options_.mapper.background_wait = options_.wait_for_perception;
  mapper_ = std::make_unique<mapping::Mapper>(options_.mapper, options_.odometry, initial_pose);
  StartPerception();
}

LiveSystem::~LiveSystem() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void LiveSystem::StartPerception() {
  if (rig_ == nullptr) return;
  front_end_ = std::make_unique<perception::PerceptionFrontEnd>(*rig_, options_.perception);
  thread_ = std::thread([this] { PerceptionLoop(); });
}

void LiveSystem::PerceptionLoop() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    wake_.wait(lock, [this] { return stop_ || queued_.has_value(); });
    if (stop_) return;
    auto [number, frame] = std::move(*queued_);
    queued_.reset();
    working_on_ = number;
    lock.unlock();
    // As perception::PerceptionSource: black or frozen cameras are left
    // out while they are so. The slots first, into the estimator at once
    // (the frame's first pose), then the tags (paper III-A, III-B).
    std::exception_ptr error;
    const Clock::time_point start = Clock::now();
    try {
      const std::vector<perception::CameraHealth> health = health_.Check(frame);
      std::vector<std::string> excluded;
      for (size_t k = 0; k < health.size(); ++k) {
        if (health[k] != perception::CameraHealth::kOk) excluded.push_back(frame.cameras[k]);
      }
      perception::PerceptionOutput out;
      out.slots.t_ns = out.tags.t_ns = frame.t_ns;
      front_end_->PerceiveSlots(frame, excluded, &out);
      {
        std::lock_guard<std::mutex> state(state_mutex_);
        Resolve(number, SensorEvent(std::move(out.slots)), true);
      }
      // While the localizer tracks, the tags are looked for where the map
      // has them, from the pose the slots just gave.
      std::optional<std::vector<perception::TagWindow>> windows;
      if (localizer_) {
        std::lock_guard<std::mutex> state(state_mutex_);
        windows = MapTagWindows(*front_end_, *localizer_, frame.t_ns);
      }
      front_end_->PerceiveTags(frame, excluded, &out, windows ? &*windows : nullptr);
      const double perception_ms = MsSince(start);
      std::lock_guard<std::mutex> state(state_mutex_);
      stats_.perception_ms.push_back(perception_ms);
      stats_.tag_searches_in_windows += windows.has_value();
      ++stats_.frames_perceived;
      Resolve(number, SensorEvent(std::move(out.tags)), false);
    } catch (...) {
      error = std::current_exception();
      std::lock_guard<std::mutex> state(state_mutex_);
      try {
        Resolve(number, std::nullopt, false);  // the queue goes on without it
      } catch (...) {
      }
    }
    lock.lock();
    working_on_ = 0;
    done_up_to_ = number;
    if (error && !error_) error_ = error;
    wake_.notify_all();
  }
}

void LiveSystem::RethrowPerceptionError() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
}

void LiveSystem::Process(SensorEvent event) {
  const Clock::time_point arrived = Clock::now();
  RethrowPerceptionError();
  std::uint64_t wait_for = 0;
  {
    std::lock_guard<std::mutex> state(state_mutex_);
    if (IsOdometry(event)) {
      // The prediction's dead reckoning starts as the estimators' do, at
      // the first IMU sample (with its heading, where the IMU has one):
      // only its motion is used.
      if (const auto* imu = std::get_if<ImuSample>(&event); imu && !ahead_.initialized()) {
        ahead_.InitializeFromHeading(imu->t_ns, Eigen::Vector2d::Zero(), imu->heading_rad);
      }
      if (ahead_.initialized() && ahead_.Process(event)) {
        ahead_track_.emplace_back(ahead_.time_ns(), ahead_.pose());
      }
    }
    if (auto* frame = std::get_if<CameraFrame>(&event)) {
      if (rig_ == nullptr) {
        throw std::invalid_argument("live: a camera frame came, and the system has no rig");
      }
      ++stats_.camera_frames;
      const std::uint64_t number = next_frame_++;
      // Its place goes before the odometry held back that is newer than it.
      const TimeNs t_ns = frame->t_ns;
      pending_.insert(options_.reorder_window_s > 0.0 ? PlaceFor(t_ns) : pending_.end(),
                      {std::nullopt, number, arrived, false, t_ns});
      std::optional<std::uint64_t> dropped;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        // Perception is behind: the frame that has waited gives way.
        if (queued_) dropped = queued_->first;
        queued_.emplace(number, std::move(*frame));
      }
      wake_.notify_all();
      if (dropped) {
        ++stats_.frames_dropped;
        Resolve(*dropped, std::nullopt, false);
      }
      if (options_.wait_for_perception) wait_for = number;
    } else {
      if (IsOdometry(event)) {
        // In time order among the odometry held back (with a window; else
        // at the end, as it came).
        const TimeNs t_ns = EventTime(event);
        newest_odometry_ns_ = std::max(newest_odometry_ns_, t_ns);
        pending_.insert(options_.reorder_window_s > 0.0 ? PlaceFor(t_ns) : pending_.end(),
                        {std::move(event), 0, arrived, false, t_ns});
      } else {
        // A slot or tag frame of the caller's, as a camera frame's place.
        const TimeNs t_ns = EventTime(event);
        pending_.insert(options_.reorder_window_s > 0.0 ? PlaceFor(t_ns) : pending_.end(),
                        {std::move(event), 0, arrived, false, t_ns});
      }
      Drain();
    }
  }
  if (wait_for != 0) WaitForFrame(wait_for);
}

void LiveSystem::WaitForFrame(std::uint64_t frame) {
  std::unique_lock<std::mutex> lock(mutex_);
  wake_.wait(lock, [&] { return error_ || done_up_to_ >= frame; });
}

void LiveSystem::Resolve(std::uint64_t frame, std::optional<SensorEvent> event, bool keep_place) {
  for (auto it = pending_.begin(); it != pending_.end(); ++it) {
    if (it->event || it->frame != frame) continue;
    const Clock::time_point arrived = it->arrived;
    // The frame's slot frame, then its tag frame (of the same time), go in
    // before its place, as a recording's stream gives them.
    const TimeNs t_ns = it->t_ns;
    if (event) it = std::next(pending_.insert(it, {std::move(event), 0, arrived, true, t_ns}));
    if (!keep_place) pending_.erase(it);
    break;
  }
  Drain();
}

std::deque<LiveSystem::Pending>::iterator LiveSystem::PlaceFor(TimeNs t_ns) {
  auto place = pending_.end();
  while (place != pending_.begin()) {
    const auto before = std::prev(place);
    if (before->t_ns <= t_ns) break;
    place = before;
  }
  return place;
}

bool LiveSystem::Ready(std::deque<Pending>::const_iterator it) const {
  if (!it->event) return false;  // a frame still being perceived
  if (!IsOdometry(*it->event) || options_.reorder_window_s <= 0.0 || finishing_) return true;
  // Held back for frames that may still arrive, unless one behind it needs it.
  if (EventTime(*it->event) <= newest_odometry_ns_ - FromSeconds(options_.reorder_window_s)) {
    return true;
  }
  return std::any_of(std::next(it), pending_.cend(),
                     [](const Pending& p) { return !p.event || !IsOdometry(*p.event); });
}

void LiveSystem::Drain() {
  while (!pending_.empty() && Ready(pending_.cbegin())) {
    Pending next = std::move(pending_.front());
    pending_.pop_front();
    Feed(*next.event, next);
  }
  PruneAheadTrack();
}

void LiveSystem::PruneAheadTrack() {
  const TimeNs base_ns = mapper_          ? mapper_->current_time_ns()
                         : last_estimate_ ? last_estimate_->first
                                          : std::numeric_limits<TimeNs>::min();
  while (ahead_track_.size() > 1 && ahead_track_[1].first <= base_ns) ahead_track_.pop_front();
}

void LiveSystem::Feed(const SensorEvent& event, const Pending& from) {
  if (mapper_) {
    mapper_->Process(event);
    return;
  }
  if (std::optional<localization::LocalizationEstimate> estimate = localizer_->Process(event)) {
    // A camera frame's first pose (its slots') is its latency; the second
    // (its tags') completes it.
    const bool second = from.perceived && std::holds_alternative<TagObservationFrame>(event);
    (second ? stats_.complete_latency_ms : stats_.latency_ms).push_back(MsSince(from.arrived));
    ++stats_.estimates;
    last_estimate_.emplace(estimate->t_ns, estimate->T_map_vehicle);
    if (options_.on_estimate) {
      options_.on_estimate(*estimate);
    } else {
      estimates_.push_back(std::move(*estimate));
    }
  }
}

std::vector<localization::LocalizationEstimate> LiveSystem::TakeEstimates() {
  RethrowPerceptionError();
  std::lock_guard<std::mutex> state(state_mutex_);
  return std::exchange(estimates_, {});
}

LiveStats LiveSystem::stats() const {
  std::lock_guard<std::mutex> state(state_mutex_);
  return stats_;
}

std::optional<TimedPose> LiveSystem::PredictedPose() const {
  std::lock_guard<std::mutex> state(state_mutex_);
  std::optional<std::pair<TimeNs, SE2>> base = last_estimate_;
  if (mapper_ && !mapper_->keyframes().empty()) {
    base.emplace(mapper_->current_time_ns(), mapper_->CurrentPose());
  }
  if (!base) return std::nullopt;
  // T_map_now = T_map_base T_ahead(base)^-1 T_ahead(now): the dead
  // reckoning's motion from the base's time to its newest.
  const std::pair<TimeNs, SE2>* at_base = nullptr;
  for (const auto& sample : ahead_track_) {
    if (sample.first > base->first) break;
    at_base = &sample;
  }
  if (at_base == nullptr) return TimedPose{base->first, base->second};
  const std::pair<TimeNs, SE2>& now = ahead_track_.back();
  return TimedPose{now.first, base->second * (at_base->second.inverse() * now.second)};
}

SemanticMap LiveSystem::Map() const {
  std::lock_guard<std::mutex> state(state_mutex_);
  return mapper_ ? mapper_->Map() : map_;
}

Trajectory LiveSystem::KeyframeTrajectory() const {
  std::lock_guard<std::mutex> state(state_mutex_);
  return mapper_ ? mapper_->KeyframeTrajectory() : Trajectory{};
}

void LiveSystem::Finish() {
  {
    std::unique_lock<std::mutex> lock(mutex_);
    wake_.wait(lock, [this] { return error_ || (!queued_ && working_on_ == 0); });
  }
  RethrowPerceptionError();
  std::lock_guard<std::mutex> state(state_mutex_);
  finishing_ = true;  // nothing more will come: the held odometry goes in
  Drain();
  if (mapper_) mapper_->Finish();
}

}  // namespace parkslam::live
