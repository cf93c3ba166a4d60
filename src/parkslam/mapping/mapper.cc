#include "parkslam/mapping/mapper.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "parkslam/common/angles.h"
#include "parkslam/common/field_checker.h"
#include "parkslam/mapping/association.h"
#include "parkslam/mapping/back_line.h"
#include "parkslam/mapping/map_graph.h"
#include "parkslam/mapping/slot_management.h"

namespace parkslam::mapping {
namespace {

double ElapsedMs(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// The batch mapper's end (paper III-C): final_rounds of a full solve, the
// records' new choices recounted, duplicates merged.
struct FinalRounds {
  int iterations = 0;
  double cost = 0.0;
  int merged = 0;
};
FinalRounds SolveFinalRounds(MapState* state, const MapperOptions& options) {
  FinalRounds result;
  for (int round = 0; round < options.final_rounds; ++round) {
    const MapGraphSolve solve = SolveMapGraph(state, 0, options.final_iterations, true, options);
    result.iterations += solve.iterations;
    result.cost = solve.final_cost;
    for (const MapGraphSolve::Choice& choice : solve.changed) {
      state->slot_records[choice.record].chosen = choice.after;
    }
    RecomputeSlotEvidence(state, options);
    result.merged += MergeDuplicates(state, options);
  }
  return result;
}

}  // namespace

bool MapperOptions::IsValid(std::string* error) const {
  FieldChecker c(error);
  c.Positive(keyframe_distance_m, "keyframe_distance_m");
  c.Positive(keyframe_yaw_rad, "keyframe_yaw_rad");
  c.Positive(idle_keyframe_distance_m, "idle_keyframe_distance_m");
  c.Positive(keyframe_interval_s, "keyframe_interval_s");
  c.Positive(min_corner_sigma_m, "min_corner_sigma_m");
  c.Positive(guessed_corner_sigma_m, "guessed_corner_sigma_m");
  c.Positive(shape_angle_sigma_rad, "shape_angle_sigma_rad");
  c.Positive(shape_length_sigma_m, "shape_length_sigma_m");
  c.Positive(corner_evidence_sigma_m, "corner_evidence_sigma_m");
  c.NonNegative(corner_sigma_floor_m, "corner_sigma_floor_m");
  c.Positive(row_depth_sigma_m, "row_depth_sigma_m");
  c.Positive(depth_prior_sigma_m, "depth_prior_sigma_m");
  c.Between(right_angle_tolerance_rad, 0.0, kPi / 2, "right_angle_tolerance_rad", "rad");
  c.Rate(id_hypothesis_min, "id_hypothesis_min");
  c.Rate(id_confidence_min, "id_confidence_min");
  c.Positive(id_search_radius_m, "id_search_radius_m");
  c.Positive(nn_search_radius_m, "nn_search_radius_m");
  c.AtLeast(max_candidates, 1, "max_candidates");
  c.NonNegative(prediction_sigma_m, "prediction_sigma_m");
  c.NonNegative(prediction_sigma_per_m, "prediction_sigma_per_m");
  c.PositiveAtMost(geometry_weight, 1.0, "geometry_weight", "");
  c.PositiveAtMost(null_weight, 1.0, "null_weight", "");
  c.Positive(null_chi2, "null_chi2");
  c.NonNegative(merge_distance_m, "merge_distance_m");
  c.AtLeast(min_observations, 1, "min_observations");
  c.Positive(id_min_votes, "id_min_votes");
  c.PositiveAtMost(max_overlap_share, 1.0, "max_overlap_share", "");
  c.AtLeast(window_keyframes, 2, "window_keyframes");
  c.AtLeast(window_history_observations, 0, "window_history_observations");
  c.AtLeast(max_records_per_landmark, 0, "max_records_per_landmark");
  c.AtLeast(retire_check_min_records, 1, "retire_check_min_records");
  c.AtLeast(online_merge_every_keyframes, 0, "online_merge_every_keyframes");
  c.AtLeast(prune_unconfirmed_after_keyframes, 0, "prune_unconfirmed_after_keyframes");
  c.AtLeast(online_iterations, 1, "online_iterations");
  // An hour at most: beyond it no drive sees a second solve (and the time
  // would overflow the clock's nanoseconds long before a double does).
  c.InRange(background_solve_every_s, 0.0, 3600.0, "background_solve_every_s", "s");
  c.AtLeast(background_iterations, 1, "background_iterations");
  c.AtLeast(batch_window_every, 1, "batch_window_every");
  c.AtLeast(final_iterations, 1, "final_iterations");
  c.AtLeast(final_rounds, 1, "final_rounds");
  // Ceres refuses a first radius outside its own bounds (min 1e-32, max
  // 1e16) and would leave the map unsolved without a word.
  c.InRange(initial_trust_region_radius, 1e-32, 1e16, "initial_trust_region_radius", "");
  c.Positive(tag_size_m, "tag_size_m");
  return c.ok();
}

Mapper::Mapper(const MapperOptions& options, const odometry::OdometryEkfOptions& ekf_options,
               std::optional<SE2> initial_pose)
    : options_(options),
      ekf_(std::make_unique<odometry::OdometryEkf>(ekf_options)),
      initial_pose_(initial_pose) {
  std::string error;
  if (!options_.IsValid(&error)) throw std::invalid_argument("mapper options: " + error);
  if (!ekf_options.IsValid(&error)) throw std::invalid_argument("odometry options: " + error);
  if (options_.estimate_wheel_scale) state_.wheel_scale_sigma = ekf_options.wheel_scale_sigma;
}

Mapper::~Mapper() = default;
Mapper::Mapper(Mapper&&) noexcept = default;
Mapper& Mapper::operator=(Mapper&&) noexcept = default;

void Mapper::Process(const SensorEvent& event) {
  const TimeNs t_ns = EventTime(event);
  if (!ekf_->initialized()) {
    if (initial_pose_) {
      ekf_->Initialize(t_ns, *initial_pose_, 0.01);
    } else if (const auto* imu = std::get_if<ImuSample>(&event)) {
      ekf_->InitializeFromHeading(t_ns, Eigen::Vector2d::Zero(), imu->heading_rad);
    } else {
      return;
    }
  }
  if (!ekf_->Process(event)) return;  // older than the filter: dropped
  const auto* slot_frame = std::get_if<SlotObservationFrame>(&event);
  const auto* tag_frame = std::get_if<TagObservationFrame>(&event);
  if (slot_frame == nullptr && tag_frame == nullptr) return;
  const auto start = std::chrono::steady_clock::now();
  const bool has_observations =
      slot_frame != nullptr ? !slot_frame->slots.empty() : !tag_frame->tags.empty();
  // One camera frame set gives a slot frame and a tag frame of the same
  // time: the second joins the keyframe the first made (it has not moved,
  // so it would never make one of its own).
  const bool same_time = !state_.keyframes.empty() && state_.keyframes.back().t_ns == t_ns;
  if (!same_time && !MaybeAddKeyframe(t_ns, has_observations)) return;
  const int k = static_cast<int>(state_.keyframes.size()) - 1;
  if (slot_frame != nullptr) {
    for (const SlotObservation& obs : slot_frame->slots) AddSlotObservation(k, obs);
  } else {
    for (const TagObservation& obs : tag_frame->tags) AddTag(k, obs);
  }
  if (same_time) return;  // these observations join the next solve
  AfterKeyframe();
  const double waited_ms = MaybeApplyBackgroundSolve(t_ns);
  RetireOldRecords();
  MaybeMergeOnline();
  MaybeStartBackgroundSolve(t_ns);
  stats_.keyframe_update_ms.push_back(ElapsedMs(start) - waited_ms);
}

bool Mapper::BackgroundRunning() const { return background_ != nullptr && background_->running(); }

double Mapper::MaybeApplyBackgroundSolve(TimeNs t_ns) {
  if (!BackgroundRunning()) return 0.0;
  const bool ready = options_.background_wait ? t_ns >= background_due_ns_ : background_->done();
  return ready ? ApplyBackgroundSolve() : 0.0;
}

void Mapper::MaybeStartBackgroundSolve(TimeNs t_ns) {
  if (options_.mode != MappingMode::kOnline || options_.background_solve_every_s <= 0.0) return;
  if (BackgroundRunning()) return;
  if (background_ == nullptr) background_ = std::make_unique<BackgroundSolve>();
  background_->Start(state_, mirror_stale_, options_.background_iterations, options_);
  mirror_stale_ = false;
  background_due_ns_ = t_ns + FromSeconds(options_.background_solve_every_s);
}

double Mapper::ApplyBackgroundSolve() {
  const auto wait_start = std::chrono::steady_clock::now();
  const MapGraphSolve solve = background_->Wait();
  const double waited_ms = ElapsedMs(wait_start);
  stats_.background_wait_ms += waited_ms;
  stats_.background_solve_ms.push_back(background_->last_solve_ms());
  ++stats_.background_solves;
  const MapState& solved = background_->solved();
  const size_t keyframes = background_->keyframes();
  if (keyframes == 0) return waited_ms;
  // Nothing was restructured while it ran (RetireOldRecords and
  // MaybeMergeOnline wait for it), so the state holds the mirror's
  // keyframes, slots, tags and records first, and what came since after
  // them. Those move with the correction of the newest keyframe the solve
  // knew: T_new = T_solved(n-1) T_now(n-1)^-1 T_now.
  const int newest = static_cast<int>(keyframes) - 1;
  const SE2 correction = solved.PoseOf(newest) * state_.PoseOf(newest).inverse();
  for (size_t k = 0; k < state_.keyframes.size(); ++k) {
    std::array<double, 3>& pose = state_.keyframes[k].pose;
    if (k < keyframes) {
      pose = solved.keyframes[k].pose;
    } else {
      const SE2 moved = correction * state_.PoseOf(static_cast<int>(k));
      pose = {moved.x(), moved.y(), moved.yaw()};
    }
  }
  state_.wheel_scale_error = solved.wheel_scale_error;
  for (size_t s = 0; s < state_.slots.size(); ++s) {
    SlotLandmark& slot = state_.slots[s];
    if (s < background_->slots()) {
      slot.corners = solved.slots[s].corners;
      continue;
    }
    for (std::array<double, 2>& c : slot.corners) {
      const Eigen::Vector2d moved = correction * Eigen::Vector2d(c[0], c[1]);
      c = {moved.x(), moved.y()};
    }
  }
  for (size_t t = 0; t < state_.tags.size(); ++t) {
    std::array<double, 3>& pose = state_.tags[t].pose;
    if (t < background_->tags()) {
      pose = solved.tags[t].pose;
    } else {
      const SE2 moved = correction * SE2(pose[0], pose[1], pose[2]);
      pose = {moved.x(), moved.y(), moved.yaw()};
    }
  }
  // The records whose mixture picks another slot at the solution move their
  // evidence there (a windowed solve may have moved some already).
  bool changed = false;
  for (const MapGraphSolve::Choice& choice : solve.changed) {
    SlotRecord& record = state_.slot_records[choice.record];
    if (record.chosen == choice.after) continue;
    MoveEvidence(&state_, record, record.chosen, -1, options_);
    MoveEvidence(&state_, record, choice.after, +1, options_);
    record.chosen = choice.after;
    changed = true;
  }
  if (changed) RebuildIdOwners(&state_);
  // A slot made twice (a loop closed late) now lies on its twin: merged
  // now, not at the end, so the map along the drive has it once.
  merge_pending_ = true;
  return waited_ms;
}

bool Mapper::MaybeAddKeyframe(TimeNs t_ns, bool has_observations) {
  const odometry::OdometryEkf::RelativeMotion motion = ekf_->MotionSinceClone();
  Keyframe keyframe;
  keyframe.t_ns = t_ns;
  if (state_.keyframes.empty()) {
    const SE2 pose = ekf_->pose();
    keyframe.pose = {pose.x(), pose.y(), pose.yaw()};
  } else {
    const Keyframe& last = state_.keyframes.back();
    const double moved_m = motion.T_clone_now.translation().norm();
    const bool moved = has_observations
                           ? moved_m >= options_.keyframe_distance_m ||
                                 std::abs(motion.T_clone_now.yaw()) >= options_.keyframe_yaw_rad
                           : moved_m >= options_.idle_keyframe_distance_m;
    if (!moved && ToSeconds(t_ns - last.t_ns) < options_.keyframe_interval_s) return false;
    const SE2 pose =
        state_.PoseOf(static_cast<int>(state_.keyframes.size()) - 1) * motion.T_clone_now;
    keyframe.pose = {pose.x(), pose.y(), pose.yaw()};
    keyframe.T_previous_this = motion.T_clone_now;
    keyframe.odometry_wheel_scale = ekf_->state()[odometry::OdometryEkf::kWheelScale];
    // A floor keeps the information finite when the car stands still.
    keyframe.covariance = 0.5 * (motion.covariance + motion.covariance.transpose()) +
                          Eigen::Matrix3d::Identity() * 1e-8;
    distance_since_solve_m_ += moved_m;
  }
  ekf_->ClonePose();
  state_.keyframes.push_back(keyframe);
  ++stats_.keyframes;
  return true;
}

void Mapper::AddSlotObservation(int keyframe, const SlotObservation& obs) {
  if (!PlausibleSlot(obs)) {
    ++stats_.rejected_slot_observations;
    return;
  }
  ++stats_.slot_observations;
  const double prediction_sigma_m =
      options_.prediction_sigma_m + options_.prediction_sigma_per_m * distance_since_solve_m_;
  SlotAssociation association = AssociateSlot(state_, keyframe, obs, prediction_sigma_m, options_);
  if (association.new_slot) {
    CreateSlot(&state_, keyframe, obs, options_);
    ++stats_.slots_created;
    return;
  }
  if (association.record.candidates.size() > 1) ++stats_.mixture_observations;
  AddSlotRecord(&state_, std::move(association.record), options_);
}

void Mapper::AddTag(int keyframe, const TagObservation& obs) {
  ++stats_.tag_observations;
  auto it = state_.tag_index.find(obs.tag_id);
  if (it == state_.tag_index.end()) {
    const SE2 pose = state_.PoseOf(keyframe);
    const Eigen::Vector2d p = pose * obs.p_vehicle;
    TagLandmark tag;
    tag.tag_id = obs.tag_id;
    tag.pose = {p.x(), p.y(), NormalizeAngle(pose.yaw() + obs.yaw_vehicle_rad)};
    state_.tags.push_back(tag);
    it = state_.tag_index.emplace(obs.tag_id, static_cast<int>(state_.tags.size()) - 1).first;
  }
  ++state_.tags[it->second].observations;
  if (state_.tag_record_index.size() < state_.tags.size())
    state_.tag_record_index.resize(state_.tags.size());
  state_.tag_record_index[static_cast<size_t>(it->second)].push_back(state_.tag_records.size());
  state_.tag_records.push_back({keyframe, obs, it->second});
}

void Mapper::AfterKeyframe() {
  const int count = static_cast<int>(state_.keyframes.size());
  const int every = options_.mode == MappingMode::kOnline ? 1 : options_.batch_window_every;
  if (count % every != 0) return;
  Solve(std::max(0, count - options_.window_keyframes), options_.online_iterations);
}

void Mapper::Solve(int first_free, int max_iterations) {
  if (state_.keyframes.empty()) return;
  const MapGraphSolve solve = SolveMapGraph(&state_, first_free, max_iterations, false, options_);
  stats_.max_window_residual_blocks =
      std::max(stats_.max_window_residual_blocks, solve.residual_blocks);
  // A record that changed its slot moves its evidence from one to the other
  // (counting every record after every windowed solve grew with the drive).
  for (const MapGraphSolve::Choice& choice : solve.changed) {
    SlotRecord& record = state_.slot_records[choice.record];
    MoveEvidence(&state_, record, choice.before, -1, options_);
    MoveEvidence(&state_, record, choice.after, +1, options_);
    record.chosen = choice.after;
  }
  if (!solve.changed.empty()) RebuildIdOwners(&state_);
  distance_since_solve_m_ = 0.0;
}

void Mapper::RetireOldRecords() {
  const int cap = options_.max_records_per_landmark;
  const size_t stored = state_.slot_records.size() + state_.tag_records.size();
  if (stored >= static_cast<size_t>(options_.retire_check_min_records)) long_drive_ = true;
  // Waits for a background solve, which will lay its solution into these
  // same records and keyframes.
  if (cap <= 0 || BackgroundRunning() ||
      stored < std::max(retire_check_at_, static_cast<size_t>(options_.retire_check_min_records))) {
    return;
  }
  mirror_stale_ = true;
  // A landmark over the cap loses every second record outside the window:
  // thinned evenly, it keeps observations from every pass, and with them
  // what ties the passes (and the loops of the drive) together; retiring
  // the oldest instead lets the map drift with the odometry (measured in
  // SoakTest). Records come in keyframe order, so each list is oldest
  // first and ends with the window's.
  const int first_free =
      std::max(0, static_cast<int>(state_.keyframes.size()) - options_.window_keyframes);
  auto thin = [&](const std::vector<std::vector<size_t>>& index, auto keyframe_of,
                  std::vector<bool>* retire) {
    for (const std::vector<size_t>& own : index) {
      if (static_cast<int>(own.size()) <= cap) continue;
      bool odd = false;
      for (const size_t r : own) {
        if (keyframe_of(r) >= first_free) break;
        if ((*retire)[r]) continue;  // already retired through another candidate
        if (odd) (*retire)[r] = true;
        odd = !odd;
      }
    }
  };
  std::vector<bool> retire_slot(state_.slot_records.size(), false),
      retire_tag(state_.tag_records.size(), false);
  thin(
      state_.slot_record_index, [&](size_t r) { return state_.slot_records[r].keyframe; },
      &retire_slot);
  thin(
      state_.tag_record_index, [&](size_t r) { return state_.tag_records[r].keyframe; },
      &retire_tag);

  // Compacted in place: storage that is reused, not reallocated, keeps the
  // resident size from creeping with the allocator's leftovers.
  size_t kept_slots = 0;
  for (size_t r = 0; r < state_.slot_records.size(); ++r) {
    SlotRecord& record = state_.slot_records[r];
    if (!retire_slot[r]) {
      if (kept_slots != r) state_.slot_records[kept_slots] = std::move(record);
      ++kept_slots;
      continue;
    }
    ++stats_.records_retired;
    if (record.chosen < 0) continue;
    // Its evidence is already counted in the slot it chose; keep it there.
    SlotLandmark& slot = state_.slots[record.chosen];
    AddEvidence(record, +1, options_, &slot.retired_votes, &slot.retired_observations,
                &slot.retired_corner_observations);
  }
  state_.slot_records.resize(kept_slots);
  size_t kept_tags = 0;
  for (size_t r = 0; r < state_.tag_records.size(); ++r) {
    if (retire_tag[r]) {
      ++stats_.records_retired;
    } else {
      if (kept_tags != r) state_.tag_records[kept_tags] = state_.tag_records[r];
      ++kept_tags;
    }
  }
  state_.tag_records.resize(kept_tags);
  CullKeyframes();
  state_.RebuildRecordIndexes();
  retire_check_at_ = 2 * (state_.slot_records.size() + state_.tag_records.size());
}

void Mapper::CullKeyframes() {
  const int n = static_cast<int>(state_.keyframes.size());
  if (n == 0) return;
  // The window's keyframes and the fixed one before it stay, and the first
  // (the map's anchor), and every keyframe a record names.
  std::vector<bool> keep(static_cast<size_t>(n), false);
  keep[0] = true;
  for (int k = std::max(0, n - options_.window_keyframes - 1); k < n; ++k)
    keep[static_cast<size_t>(k)] = true;
  for (const SlotRecord& record : state_.slot_records)
    keep[static_cast<size_t>(record.keyframe)] = true;
  for (const TagRecord& record : state_.tag_records)
    keep[static_cast<size_t>(record.keyframe)] = true;

  // T_a_b = T_a_k T_k_b, and to first order, with e = (t, yaw) of a
  // relative pose as the odometry factor takes it:
  //   Sigma_a_b = J1 Sigma_a_k J1^T + J2 Sigma_k_b J2^T,
  //   J1 = [I  R(yaw_a_k) [-y_k_b, x_k_b]^T; 0 0 1],  J2 = [R(yaw_a_k) 0; 0 1].
  std::vector<int> new_index(static_cast<size_t>(n), -1);
  size_t kept = 0;  // compacted in place, as the records
  SE2 T_a_k;
  Eigen::Matrix3d sigma_a_k = Eigen::Matrix3d::Zero();
  for (int k = 0; k < n; ++k) {
    Keyframe keyframe = state_.keyframes[static_cast<size_t>(k)];
    if (k > 0) {
      const SE2& T_k_b = keyframe.T_previous_this;
      const Eigen::Matrix2d R = T_a_k.rotation();
      Eigen::Matrix3d J1 = Eigen::Matrix3d::Identity(), J2 = Eigen::Matrix3d::Identity();
      J1.block<2, 1>(0, 2) = R * Eigen::Vector2d(-T_k_b.translation().y(), T_k_b.translation().x());
      J2.block<2, 2>(0, 0) = R;
      sigma_a_k = J1 * sigma_a_k * J1.transpose() + J2 * keyframe.covariance * J2.transpose();
      T_a_k = T_a_k * T_k_b;
    }
    if (!keep[static_cast<size_t>(k)]) {
      ++stats_.keyframes_culled;
      continue;
    }
    if (k > 0) {
      keyframe.T_previous_this = T_a_k;
      keyframe.covariance = 0.5 * (sigma_a_k + sigma_a_k.transpose());
    }
    T_a_k = SE2();
    sigma_a_k.setZero();
    new_index[static_cast<size_t>(k)] = static_cast<int>(kept);
    state_.keyframes[kept++] = keyframe;
  }
  if (static_cast<int>(kept) == n) return;
  state_.keyframes.resize(kept);
  for (SlotRecord& record : state_.slot_records)
    record.keyframe = new_index[static_cast<size_t>(record.keyframe)];
  for (TagRecord& record : state_.tag_records)
    record.keyframe = new_index[static_cast<size_t>(record.keyframe)];
}

void Mapper::MaybeMergeOnline() {
  const int every = options_.online_merge_every_keyframes;
  if (long_drive_ && every > 0 && state_.keyframes.size() % static_cast<size_t>(every) == 0) {
    prune_pending_ = true;
  }
  if ((!prune_pending_ && !merge_pending_) || BackgroundRunning()) return;
  const int pruned = prune_pending_ ? PruneUnconfirmedSlots(&state_, options_) : 0;
  prune_pending_ = merge_pending_ = false;
  const int merged = MergeDuplicates(&state_, options_);
  stats_.slots_pruned += pruned;
  stats_.slots_merged += merged;
  if (pruned == 0 && merged == 0) return;
  mirror_stale_ = true;
  RecomputeSlotEvidence(&state_, options_);
  state_.RebuildRecordIndexes();
}

void Mapper::Finish() {
  const auto start = std::chrono::steady_clock::now();
  if (BackgroundRunning()) ApplyBackgroundSolve();
  if (options_.mode == MappingMode::kBatch) {
    const FinalRounds rounds = SolveFinalRounds(&state_, options_);
    stats_.final_iterations += rounds.iterations;
    stats_.final_cost = rounds.cost;
    stats_.slots_merged += rounds.merged;
    distance_since_solve_m_ = 0.0;
  } else {
    RecomputeSlotEvidence(&state_, options_);
    stats_.slots_merged += MergeDuplicates(&state_, options_);
  }
  RecomputeSlotEvidence(&state_, options_);
  AssignIds(&state_, options_);
  finished_ = true;
  stats_.slots_overlapping += DropOverlappingSlots(&state_, options_);
  // Left empty when it cannot be computed: Map() takes the sightings' sigmas.
  corner_covariances_.clear();
  const auto covariance_start = std::chrono::steady_clock::now();
  if (options_.corner_sigma_from_graph) {
    ComputeCornerCovariances(&state_, options_, &corner_covariances_);
  }
  stats_.covariance_ms = ElapsedMs(covariance_start);
  stats_.final_solve_ms = ElapsedMs(start);
}

SemanticMap Mapper::Map() const { return Map(options_.min_observations); }

SemanticMap Mapper::Map(int min_observations) const {
  // Before Finish the slots are named as they would be if the drive ended
  // now; Finish names them for good (and may drop some after).
  const std::vector<std::string> ids =
      finished_ ? std::vector<std::string>() : IdsByVotes(state_.slots, options_);
  return MapOf(state_, options_, corner_covariances_, min_observations, ids);
}

SemanticMap Mapper::BatchMapSoFar(int min_observations) const {
  MapState state = state_;
  SolveFinalRounds(&state, options_);
  return MapOf(state, options_, {}, min_observations, IdsByVotes(state.slots, options_));
}

SemanticMap Mapper::MapOf(const MapState& state, const MapperOptions& options,
                          const CornerCovariances& corner_covariances, int min_observations,
                          const std::vector<std::string>& ids) {
  SemanticMap map;
  map.metadata["source"] = "parkslam mapper";
  map.metadata["robust"] = options.robust == RobustMode::kMaxMixture ? "maxmix" : "none";
  map.metadata["mode"] = options.mode == MappingMode::kBatch ? "batch" : "online";
  if (state.wheel_scale_sigma > 0.0) {
    map.metadata["wheel_scale_error"] = std::to_string(state.wheel_scale_error[0]);
  }
  if (!state.keyframes.empty()) map.entrance = state.PoseOf(0);
  for (size_t index = 0; index < state.slots.size(); ++index) {
    const SlotLandmark& slot = state.slots[index];
    if (!slot.alive || slot.observations < min_observations) continue;
    MapSlot s;
    const std::string& id = ids.empty() ? slot.id : ids[index];
    s.id = id.empty() ? TemporaryId(slot.temporary_number) : id;
    s.temporary = id.empty();
    if (std::abs(slot.angle_rad - kPi / 2) > 1e-6) {
      s.kind = SlotKind::kAngled;
    } else {
      s.kind = slot.width_m > 4.0 ? SlotKind::kParallel : SlotKind::kPerpendicular;
    }
    for (int j = 0; j < kSlotCorners; ++j) {
      s.corners_map[j] = slot.Corner(j);
      s.corner_observed[j] = slot.corner_observations[j] > 0;
      // Seen: the graph's marginal (or the detector's sigma over the
      // evidence) above the floor. Far corners not seen: ShareBackLines.
      const bool from_graph =
          index < corner_covariances.size() && corner_covariances[index][j].has_value();
      if (!s.corner_observed[j]) {
        s.corner_sigma_m[j] = options.depth_prior_sigma_m;
      } else if (from_graph) {
        s.corner_sigma_m[j] = std::hypot(std::sqrt(0.5 * corner_covariances[index][j]->trace()),
                                         options.corner_sigma_floor_m);
      } else {
        const double n = slot.corner_observations[j];
        s.corner_sigma_m[j] = std::hypot(options.corner_evidence_sigma_m / std::sqrt(n),
                                         options.corner_sigma_floor_m);
      }
    }
    s.observation_count = slot.observations;
    map.slots.push_back(s);
  }
  BackLineOptions back_line;
  back_line.row_depth_sigma_m = options.row_depth_sigma_m;
  back_line.depth_prior_sigma_m = options.depth_prior_sigma_m;
  ShareBackLines(back_line, &map.slots);
  // Each tag implies an obstacle: the face of the wall or pillar it hangs on,
  // drawn as a segment one metre wide behind it.
  for (const TagLandmark& tag : state.tags) {
    const Eigen::Vector2d p(tag.pose[0], tag.pose[1]);
    const Eigen::Vector2d along(-std::sin(tag.pose[2]), std::cos(tag.pose[2]));
    map.obstacles.push_back({ObstacleKind::kWall, {p - 0.5 * along, p + 0.5 * along}});
    map.tags.push_back({tag.tag_id,
                        p,
                        tag.pose[2],
                        options.tag_size_m,
                        static_cast<int>(map.obstacles.size()) - 1,
                        {}});
  }
  return map;
}

SE2 Mapper::CurrentPose() const {
  if (state_.keyframes.empty()) return SE2();
  return state_.PoseOf(static_cast<int>(state_.keyframes.size()) - 1) *
         ekf_->MotionSinceClone().T_clone_now;
}

Trajectory Mapper::KeyframeTrajectory() const {
  Trajectory trajectory;
  for (int k = 0; k < static_cast<int>(state_.keyframes.size()); ++k) {
    trajectory.push_back({state_.keyframes[k].t_ns, state_.PoseOf(k)});
  }
  return trajectory;
}

}  // namespace parkslam::mapping
