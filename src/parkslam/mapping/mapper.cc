#include "parkslam/mapping/mapper.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

#include "parkslam/common/angles.h"
#include "parkslam/mapping/costs/angle.h"
#include "parkslam/mapping/costs/max_mixture_corner_factor.h"
#include "parkslam/mapping/costs/odometry_factor.h"
#include "parkslam/mapping/costs/slot_shape_factor.h"
#include "parkslam/mapping/costs/tag_observation_factor.h"
#include "parkslam/mapping/slot_id.h"

namespace parkslam::mapping {
namespace {

double Square(double x) { return x * x; }

Eigen::Vector2d CornerOf(const Mapper::SlotLandmark& slot, int j) {
  return {slot.corners[j][0], slot.corners[j][1]};
}

// Per-corner standard deviation of an observation: the detector's for seen
// corners (with a floor), a loose one for guessed corners.
double CornerSigma(const SlotObservation& obs, int j, const MapperOptions& o) {
  return obs.corner_observed[j] ? std::max(obs.corner_sigma_m, o.min_corner_sigma_m)
                                : o.guessed_corner_sigma_m;
}

double ElapsedMs(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// The corner angle of a slot observation at corner 0, counter-clockwise
// from the entrance to the side; plausible slots lie in (0, pi).
double SlotAngle(const SlotObservation& obs) {
  const Eigen::Vector2d entrance = obs.corners_vehicle[1] - obs.corners_vehicle[0];
  const Eigen::Vector2d side = obs.corners_vehicle[3] - obs.corners_vehicle[0];
  return std::atan2(entrance.x() * side.y() - entrance.y() * side.x(), entrance.dot(side));
}

bool PlausibleSlot(const SlotObservation& obs) {
  constexpr double kMinAngleRad = 0.35, kMinSideM = 0.5;  // 20 degrees
  const double angle = SlotAngle(obs);
  bool finite = true;
  for (const Eigen::Vector2d& c : obs.corners_vehicle) finite &= c.allFinite();
  return finite && angle > kMinAngleRad && angle < kPi - kMinAngleRad &&
         (obs.corners_vehicle[1] - obs.corners_vehicle[0]).norm() > kMinSideM &&
         (obs.corners_vehicle[3] - obs.corners_vehicle[0]).norm() > kMinSideM;
}

// The records a bounded windowed solve takes (MapperOptions::
// window_history_observations), in order: the window's, which are the last
// ones since records come in keyframe order, and for each landmark they
// name (added to *free) its latest `history` older ones, from `index`
// (landmark -> its records, oldest first). The work does not grow with the
// drive.
template <typename Record, typename Landmarks>
std::vector<size_t> BoundedWindowRecords(const std::vector<Record>& records,
                                         const std::vector<std::vector<size_t>>& index,
                                         int first_free, int history, Landmarks landmarks_of,
                                         std::set<int>* free) {
  std::vector<size_t> in_play;
  for (size_t r = records.size(); r-- > 0 && records[r].keyframe >= first_free;) {
    for (int landmark : landmarks_of(records[r])) free->insert(landmark);
    in_play.push_back(r);
  }
  for (int landmark : *free) {
    const std::vector<size_t>& own = index[static_cast<size_t>(landmark)];
    int taken = 0;
    for (size_t i = own.size(); i-- > 0 && taken < history;) {
      if (records[own[i]].keyframe >= first_free) continue;
      in_play.push_back(own[i]);
      ++taken;
    }
  }
  std::sort(in_play.begin(), in_play.end());
  in_play.erase(std::unique(in_play.begin(), in_play.end()), in_play.end());
  return in_play;
}

}  // namespace

bool MapperOptions::IsValid(std::string* error) const {
  auto fail = [error](const char* message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (!(keyframe_distance_m > 0 && keyframe_yaw_rad > 0 && idle_keyframe_distance_m > 0 &&
        keyframe_interval_s > 0))
    return fail("keyframe thresholds must be positive");
  if (!(min_corner_sigma_m > 0 && guessed_corner_sigma_m > 0))
    return fail("corner sigmas must be positive");
  if (!(shape_angle_sigma_rad > 0 && shape_length_sigma_m > 0))
    return fail("shape sigmas must be positive");
  if (!(nn_search_radius_m > 0 && id_search_radius_m > 0 && max_candidates >= 1))
    return fail("search radii must be positive and max_candidates at least 1");
  if (!(geometry_weight > 0 && geometry_weight <= 1 && null_weight > 0 && null_weight <= 1 &&
        null_chi2 > 0))
    return fail("mixture weights must be in (0, 1] and null_chi2 positive");
  if (!(merge_distance_m >= 0 && min_observations >= 1 && id_min_votes > 0))
    return fail("slot management thresholds out of range");
  if (!(window_keyframes >= 2 && window_history_observations >= 0 && online_iterations >= 1 &&
        batch_window_every >= 1 && final_iterations >= 1 && final_rounds >= 1))
    return fail("solver settings out of range");
  if (!(max_records_per_landmark >= 0 && retire_check_min_records >= 1 &&
        online_merge_every_keyframes >= 0 && prune_unconfirmed_after_keyframes >= 0))
    return fail(
        "max_records_per_landmark, online_merge_every_keyframes and "
        "prune_unconfirmed_after_keyframes "
        "must be >= 0, retire_check_min_records >= 1");
  // Ceres refuses a first radius outside its own bounds (min 1e-32, max
  // 1e16) and would leave the map unsolved without a word.
  if (!(initial_trust_region_radius >= 1e-32 && initial_trust_region_radius <= 1e16))
    return fail("initial_trust_region_radius must be in [1e-32, 1e16]");
  return true;
}

Mapper::Mapper(const MapperOptions& options, const odometry::OdometryEkfOptions& ekf_options,
               std::optional<SE2> initial_pose)
    : options_(options),
      ekf_(std::make_unique<odometry::OdometryEkf>(ekf_options)),
      initial_pose_(initial_pose) {
  std::string error;
  if (!options_.IsValid(&error)) throw std::invalid_argument("mapper options: " + error);
  if (!ekf_options.IsValid(&error)) throw std::invalid_argument("odometry options: " + error);
}

Mapper::~Mapper() = default;
Mapper::Mapper(Mapper&&) noexcept = default;
Mapper& Mapper::operator=(Mapper&&) noexcept = default;

SE2 Mapper::PoseOf(int keyframe) const {
  const auto& p = keyframes_[keyframe].pose;
  return SE2(p[0], p[1], p[2]);
}

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
  const bool same_time = !keyframes_.empty() && keyframes_.back().t_ns == t_ns;
  if (!same_time && !MaybeAddKeyframe(t_ns, has_observations)) return;
  const int k = static_cast<int>(keyframes_.size()) - 1;
  if (slot_frame != nullptr) {
    for (const SlotObservation& obs : slot_frame->slots) AssociateSlot(k, obs);
  } else {
    for (const TagObservation& obs : tag_frame->tags) AddTag(k, obs);
  }
  if (same_time) return;  // these observations join the next solve
  AfterKeyframe();
  RetireOldRecords();
  MaybeMergeOnline();
  stats_.keyframe_update_ms.push_back(ElapsedMs(start));
}

bool Mapper::MaybeAddKeyframe(TimeNs t_ns, bool has_observations) {
  const odometry::OdometryEkf::RelativeMotion motion = ekf_->MotionSinceClone();
  Keyframe keyframe;
  keyframe.t_ns = t_ns;
  if (keyframes_.empty()) {
    const SE2 pose = ekf_->pose();
    keyframe.pose = {pose.x(), pose.y(), pose.yaw()};
  } else {
    const Keyframe& last = keyframes_.back();
    const double moved_m = motion.T_clone_now.translation().norm();
    const bool moved = has_observations
                           ? moved_m >= options_.keyframe_distance_m ||
                                 std::abs(motion.T_clone_now.yaw()) >= options_.keyframe_yaw_rad
                           : moved_m >= options_.idle_keyframe_distance_m;
    if (!moved && ToSeconds(t_ns - last.t_ns) < options_.keyframe_interval_s) return false;
    const SE2 pose = PoseOf(static_cast<int>(keyframes_.size()) - 1) * motion.T_clone_now;
    keyframe.pose = {pose.x(), pose.y(), pose.yaw()};
    keyframe.T_previous_this = motion.T_clone_now;
    // A floor keeps the information finite when the car stands still.
    keyframe.covariance = 0.5 * (motion.covariance + motion.covariance.transpose()) +
                          Eigen::Matrix3d::Identity() * 1e-8;
    distance_since_solve_m_ += moved_m;
  }
  ekf_->ClonePose();
  keyframes_.push_back(keyframe);
  ++stats_.keyframes;
  return true;
}

double Mapper::IdSupport(const SlotLandmark& slot, const SlotObservation& obs) const {
  double total = 0.0;
  for (const auto& [id, votes] : slot.votes) total += votes;
  if (total <= 0.0) return 0.0;
  double support = 0.0;
  for (const IdHypothesis& h : FullIdHypotheses(obs.id, options_.id_hypothesis_min)) {
    const auto it = slot.votes.find(h.id);
    if (it != slot.votes.end()) support += h.probability * it->second / total;
  }
  const std::string pattern = PartialPattern(obs.id);
  if (!pattern.empty()) {
    // One digit read: the slot's IDs that agree with it, at the read digit's
    // confidence.
    for (const auto& [id, votes] : slot.votes) {
      if (MatchesPattern(id, pattern)) support += obs.id.confidence() * votes / total;
    }
  }
  return std::min(support, 1.0);
}

void Mapper::AssociateSlot(int keyframe, const SlotObservation& obs) {
  if (!PlausibleSlot(obs)) {
    ++stats_.rejected_slot_observations;
    return;
  }
  ++stats_.slot_observations;
  const SE2 pose = PoseOf(keyframe);
  std::array<Eigen::Vector2d, kSlotCorners> predicted;
  for (int j = 0; j < kSlotCorners; ++j) predicted[j] = pose * obs.corners_vehicle[j];
  const double prediction_sigma =
      options_.prediction_sigma_m + options_.prediction_sigma_per_m * distance_since_solve_m_;

  struct Candidate {
    int slot;
    double weight, chi2, cost, entrance_distance_m;
  };
  std::vector<Candidate> candidates;
  for (int s = 0; s < static_cast<int>(slots_.size()); ++s) {
    const SlotLandmark& slot = slots_[s];
    if (!slot.alive) continue;
    const double d0 = (CornerOf(slot, 0) - predicted[0]).norm();
    const double d1 = (CornerOf(slot, 1) - predicted[1]).norm();
    const double entrance_m = std::max(d0, d1);
    if (entrance_m > options_.id_search_radius_m) continue;
    const double support = IdSupport(slot, obs);
    const bool neighbour = entrance_m <= options_.nn_search_radius_m;
    if (!neighbour && support < options_.id_hypothesis_min) continue;
    Candidate c{s, std::min(1.0, options_.geometry_weight + support), 0.0, 0.0, entrance_m};
    for (int j = 0; j < kSlotCorners; ++j) {
      c.chi2 += (CornerOf(slot, j) - predicted[j]).squaredNorm() /
                (Square(CornerSigma(obs, j, options_)) + Square(prediction_sigma));
    }
    c.cost = -std::log(c.weight) + 0.5 * c.chi2;
    candidates.push_back(c);
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& a, const Candidate& b) { return a.cost < b.cost; });
  if (static_cast<int>(candidates.size()) > options_.max_candidates) {
    candidates.resize(options_.max_candidates);
  }

  SlotRecord record;
  record.keyframe = keyframe;
  record.observation = obs;
  if (options_.robust == RobustMode::kNone) {
    // The plain front-end of the paper's baseline: a confident ID decides;
    // otherwise the nearest neighbour within the gate; otherwise a new slot.
    int chosen = -1;
    const bool confident =
        !obs.id.empty() && !obs.id.partial() && obs.id.confidence() >= options_.id_confidence_min;
    if (confident) {
      const auto owner = id_owner_.find(obs.id.best());
      if (owner != id_owner_.end() && slots_[owner->second.first].alive) {
        const double d = (CornerOf(slots_[owner->second.first], 0) - predicted[0]).norm();
        if (d <= options_.id_search_radius_m) chosen = owner->second.first;
      }
    }
    if (chosen < 0) {
      double best_chi2 = options_.null_chi2;
      for (const Candidate& c : candidates) {
        if (c.entrance_distance_m <= options_.nn_search_radius_m && c.chi2 < best_chi2) {
          best_chi2 = c.chi2;
          chosen = c.slot;
        }
      }
    }
    if (chosen < 0) {
      CreateSlot(keyframe, obs);
      return;
    }
    record.candidates = {chosen};
    record.weights = {1.0};
    record.chosen = chosen;
  } else {
    const double null_cost = -std::log(options_.null_weight) + 0.5 * options_.null_chi2;
    if (candidates.empty() || candidates.front().cost > null_cost) {
      // Neither a confident ID nor a neighbour: a new slot, added lazily
      // under a temporary ID (paper III-C).
      CreateSlot(keyframe, obs);
      return;
    }
    for (const Candidate& c : candidates) {
      record.candidates.push_back(c.slot);
      record.weights.push_back(c.weight);
    }
    record.has_null = true;
    record.chosen = candidates.front().slot;
    if (record.candidates.size() > 1) ++stats_.mixture_observations;
  }
  MoveEvidence(record, record.chosen, +1);
  IndexSlotRecord(record);
  slot_records_.push_back(std::move(record));
  UpdateIdOwner(slot_records_.back().chosen);
}

int Mapper::CreateSlot(int keyframe, const SlotObservation& obs) {
  const SE2 pose = PoseOf(keyframe);
  SlotLandmark slot;
  for (int j = 0; j < kSlotCorners; ++j) {
    const Eigen::Vector2d p = pose * obs.corners_vehicle[j];
    slot.corners[j] = {p.x(), p.y()};
  }
  const Eigen::Vector2d entrance = obs.corners_vehicle[1] - obs.corners_vehicle[0];
  const Eigen::Vector2d side = obs.corners_vehicle[3] - obs.corners_vehicle[0];
  slot.angle_rad = SlotAngle(obs);
  if (std::abs(slot.angle_rad - kPi / 2) < options_.right_angle_tolerance_rad) {
    slot.angle_rad = kPi / 2;
  }
  slot.width_m = entrance.norm();
  slot.depth_m = side.norm();
  slot.temporary_number = next_temporary_number_++;
  slots_.push_back(slot);
  ++stats_.slots_created;
  const int index = static_cast<int>(slots_.size()) - 1;

  // The creating observation is tied to its slot without a null component,
  // so that no slot is ever left without a factor.
  SlotRecord record;
  record.keyframe = keyframe;
  record.observation = obs;
  record.candidates = {index};
  record.weights = {1.0};
  record.chosen = index;
  MoveEvidence(record, index, +1);
  IndexSlotRecord(record);
  slot_records_.push_back(std::move(record));
  UpdateIdOwner(index);
  return index;
}

void Mapper::UpdateIdOwner(int s) {
  for (const auto& [id, votes] : slots_[s].votes) {
    auto it = id_owner_.find(id);
    if (it == id_owner_.end() || !slots_[it->second.first].alive || votes > it->second.second ||
        it->second.first == s) {
      id_owner_[id] = {s, votes};
    }
  }
}

void Mapper::AddTag(int keyframe, const TagObservation& obs) {
  ++stats_.tag_observations;
  auto it = tag_index_.find(obs.tag_id);
  if (it == tag_index_.end()) {
    const SE2 pose = PoseOf(keyframe);
    const Eigen::Vector2d p = pose * obs.p_vehicle;
    TagLandmark tag;
    tag.tag_id = obs.tag_id;
    tag.pose = {p.x(), p.y(), NormalizeAngle(pose.yaw() + obs.yaw_vehicle_rad)};
    tags_.push_back(tag);
    it = tag_index_.emplace(obs.tag_id, static_cast<int>(tags_.size()) - 1).first;
  }
  ++tags_[it->second].observations;
  if (tag_record_index_.size() < tags_.size()) tag_record_index_.resize(tags_.size());
  tag_record_index_[static_cast<size_t>(it->second)].push_back(tag_records_.size());
  tag_records_.push_back({keyframe, obs, it->second});
}

void Mapper::AfterKeyframe() {
  const int count = static_cast<int>(keyframes_.size());
  const int every = options_.mode == MappingMode::kOnline ? 1 : options_.batch_window_every;
  if (count % every != 0) return;
  Solve(std::max(0, count - options_.window_keyframes), options_.online_iterations, false);
}

void Mapper::Solve(int first_free, int max_iterations, bool final) {
  const int count = static_cast<int>(keyframes_.size());
  if (count == 0) return;
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  Pose2Manifold pose_manifold;

  auto add_pose = [&](int k) {
    double* block = keyframes_[k].pose.data();
    if (!problem.HasParameterBlock(block)) {
      problem.AddParameterBlock(block, 3, &pose_manifold);
      if (k < first_free || k == 0) problem.SetParameterBlockConstant(block);
    }
    return block;
  };

  // Odometry between consecutive keyframes (the first links to the last
  // fixed one).
  for (int k = std::max(1, first_free); k < count; ++k) {
    problem.AddResidualBlock(
        OdometryFactor::Create(keyframes_[k].T_previous_this, keyframes_[k].covariance), nullptr,
        add_pose(k - 1), add_pose(k));
  }
  if (count == 1) add_pose(0);

  // Slot observations: one block per observation over all its candidates.
  // Slots seen in the window are free; their older observations enter too
  // (older poses held fixed), so a revisited slot keeps its earlier
  // evidence: outside the final solve, only the latest
  // window_history_observations of each, so that the update stays bounded.
  const int history = final ? 0 : options_.window_history_observations;
  std::set<int> free_slots;
  std::vector<size_t> slot_records_in_play;
  if (history == 0) {
    for (const SlotRecord& record : slot_records_) {
      if (record.keyframe >= first_free)
        free_slots.insert(record.candidates.begin(), record.candidates.end());
    }
    for (size_t r = 0; r < slot_records_.size(); ++r) {
      const SlotRecord& record = slot_records_[r];
      const bool touches_free = std::any_of(record.candidates.begin(), record.candidates.end(),
                                            [&](int c) { return free_slots.count(c) > 0; });
      if (record.keyframe >= first_free || touches_free) slot_records_in_play.push_back(r);
    }
  } else {
    slot_records_in_play = BoundedWindowRecords(
        slot_records_, slot_record_index_, first_free, history,
        [](const SlotRecord& record) { return record.candidates; }, &free_slots);
  }
  struct MixtureBlock {
    size_t record;
    const MaxMixtureCornerFactor* factor;
    std::vector<double*> blocks;
  };
  std::vector<MixtureBlock> mixtures;
  std::set<int> fixed_slots;
  for (const size_t r : slot_records_in_play) {
    const SlotRecord& record = slot_records_[r];
    std::vector<CornerMeasurement> measurements;
    for (int j = 0; j < kSlotCorners; ++j) {
      measurements.push_back(
          {record.observation.corners_vehicle[j],
           Eigen::Matrix2d::Identity() * Square(CornerSigma(record.observation, j, options_))});
    }
    std::vector<double*> blocks{add_pose(record.keyframe)};
    for (int s : record.candidates) {
      for (int j = 0; j < kSlotCorners; ++j) blocks.push_back(slots_[s].corners[j].data());
      if (free_slots.count(s) == 0) fixed_slots.insert(s);
    }
    auto* factor = new MaxMixtureCornerFactor(measurements, record.weights,
                                              record.has_null ? options_.null_weight : 0.0,
                                              options_.null_chi2);
    problem.AddResidualBlock(factor, nullptr, blocks);
    if (record.has_null || record.candidates.size() > 1) mixtures.push_back({r, factor, blocks});
  }
  for (int s : fixed_slots) {
    for (int j = 0; j < kSlotCorners; ++j)
      problem.SetParameterBlockConstant(slots_[s].corners[j].data());
  }
  // The rectangular constraint of every slot in play (paper III-A).
  for (int s : free_slots) {
    SlotLandmark& slot = slots_[s];
    problem.AddResidualBlock(
        SlotShapeFactor::Create(slot.angle_rad, slot.width_m, slot.depth_m,
                                options_.shape_angle_sigma_rad, options_.shape_length_sigma_m),
        nullptr, slot.corners[0].data(), slot.corners[1].data(), slot.corners[2].data(),
        slot.corners[3].data());
  }
  std::set<int> free_tags;
  std::vector<size_t> tag_records_in_play;
  if (history == 0) {
    for (const TagRecord& record : tag_records_) {
      if (record.keyframe >= first_free) free_tags.insert(record.tag);
    }
    for (size_t r = 0; r < tag_records_.size(); ++r) {
      if (free_tags.count(tag_records_[r].tag) > 0) tag_records_in_play.push_back(r);
    }
  } else {
    tag_records_in_play = BoundedWindowRecords(
        tag_records_, tag_record_index_, first_free, history,
        [](const TagRecord& record) { return std::vector<int>{record.tag}; }, &free_tags);
  }
  for (const size_t r : tag_records_in_play) {
    const TagRecord& record = tag_records_[r];
    double* tag_block = tags_[record.tag].pose.data();
    if (!problem.HasParameterBlock(tag_block)) {
      problem.AddParameterBlock(tag_block, 3, &pose_manifold);
    }
    problem.AddResidualBlock(TagObservationFactor::Create(record.observation.p_vehicle,
                                                          record.observation.yaw_vehicle_rad,
                                                          record.observation.covariance_vehicle,
                                                          record.observation.yaw_sigma_rad),
                             nullptr, add_pose(record.keyframe), tag_block);
  }

  if (!final) {
    stats_.max_window_residual_blocks =
        std::max(stats_.max_window_residual_blocks, problem.NumResidualBlocks());
  }
  ceres::Solver::Options solver_options;
  solver_options.max_num_iterations = max_iterations;
  solver_options.num_threads = 1;
  solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver_options.trust_region_strategy_type =
      options_.trust_region == TrustRegion::kDogleg ? ceres::DOGLEG : ceres::LEVENBERG_MARQUARDT;
  solver_options.initial_trust_region_radius = options_.initial_trust_region_radius;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  if (summary.termination_type == ceres::FAILURE) {
    throw std::runtime_error("Mapper: the solver refused to run or failed: " + summary.message);
  }
  if (final) {
    stats_.final_iterations += static_cast<int>(summary.iterations.size());
    stats_.final_cost = summary.final_cost;
  }

  // Which component each mixture picked at the solution. A record that
  // changed its slot moves its evidence from one to the other (the final
  // solve recounts everything; counting every record after every windowed
  // solve grew with the drive).
  bool changed = false;
  for (const MixtureBlock& m : mixtures) {
    const int component = m.factor->ChosenComponent(m.blocks.data());
    SlotRecord& record = slot_records_[m.record];
    const int chosen = component < 0 ? -1 : record.candidates[component];
    if (chosen == record.chosen) continue;
    changed = true;
    if (!final) {
      MoveEvidence(record, record.chosen, -1);
      MoveEvidence(record, chosen, +1);
    }
    record.chosen = chosen;
  }
  if (changed && final) RecomputeSlotEvidence();
  if (changed && !final) RebuildIdOwners();
  distance_since_solve_m_ = 0.0;
}

void Mapper::IndexSlotRecord(const SlotRecord& record) {
  if (slot_record_index_.size() < slots_.size()) slot_record_index_.resize(slots_.size());
  for (int c : record.candidates) {
    slot_record_index_[static_cast<size_t>(c)].push_back(slot_records_.size());
  }
}

void Mapper::MoveEvidence(const SlotRecord& record, int slot_index, int sign) {
  if (slot_index < 0) return;
  SlotLandmark& slot = slots_[slot_index];
  AddEvidence(record, sign, &slot.votes, &slot.observations, &slot.corner_observations);
}

void Mapper::AddEvidence(const SlotRecord& record, int sign, std::map<std::string, double>* votes,
                         int* observations,
                         std::array<int, kSlotCorners>* corner_observations) const {
  *observations += sign;
  for (int j = 0; j < kSlotCorners; ++j) {
    (*corner_observations)[j] += sign * static_cast<int>(record.observation.corner_observed[j]);
  }
  for (const IdHypothesis& h :
       FullIdHypotheses(record.observation.id, options_.id_hypothesis_min)) {
    double& v = (*votes)[h.id];
    v += sign * h.probability;
    if (v < 1e-9) votes->erase(h.id);  // what a removal leaves of a vote
  }
}

void Mapper::RebuildIdOwners() {
  id_owner_.clear();
  for (int s = 0; s < static_cast<int>(slots_.size()); ++s) {
    if (slots_[s].alive) UpdateIdOwner(s);
  }
}

void Mapper::RecomputeSlotEvidence() {
  for (SlotLandmark& slot : slots_) {
    slot.votes = slot.retired_votes;
    slot.observations = slot.retired_observations;
    slot.corner_observations = slot.retired_corner_observations;
  }
  for (const SlotRecord& record : slot_records_) MoveEvidence(record, record.chosen, +1);
  RebuildIdOwners();
}

void Mapper::RetireOldRecords() {
  const int cap = options_.max_records_per_landmark;
  const size_t stored = slot_records_.size() + tag_records_.size();
  if (stored >= static_cast<size_t>(options_.retire_check_min_records)) long_drive_ = true;
  if (cap <= 0 ||
      stored < std::max(retire_check_at_, static_cast<size_t>(options_.retire_check_min_records))) {
    return;
  }
  // A landmark over the cap loses every second record outside the window:
  // thinned evenly, it keeps observations from every pass, and with them
  // what ties the passes (and the loops of the drive) together; retiring
  // the oldest instead lets the map drift with the odometry (measured in
  // SoakTest). Records come in keyframe order, so each list is oldest
  // first and ends with the window's.
  const int first_free =
      std::max(0, static_cast<int>(keyframes_.size()) - options_.window_keyframes);
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
  std::vector<bool> retire_slot(slot_records_.size(), false),
      retire_tag(tag_records_.size(), false);
  thin(
      slot_record_index_, [&](size_t r) { return slot_records_[r].keyframe; }, &retire_slot);
  thin(
      tag_record_index_, [&](size_t r) { return tag_records_[r].keyframe; }, &retire_tag);

  // Compacted in place: storage that is reused, not reallocated, keeps the
  // resident size from creeping with the allocator's leftovers.
  size_t kept_slots = 0;
  for (size_t r = 0; r < slot_records_.size(); ++r) {
    SlotRecord& record = slot_records_[r];
    if (!retire_slot[r]) {
      if (kept_slots != r) slot_records_[kept_slots] = std::move(record);
      ++kept_slots;
      continue;
    }
    ++stats_.records_retired;
    if (record.chosen < 0) continue;
    // Its evidence is already counted in the slot it chose; keep it there.
    SlotLandmark& slot = slots_[record.chosen];
    AddEvidence(record, +1, &slot.retired_votes, &slot.retired_observations,
                &slot.retired_corner_observations);
  }
  slot_records_.resize(kept_slots);
  size_t kept_tags = 0;
  for (size_t r = 0; r < tag_records_.size(); ++r) {
    if (retire_tag[r]) {
      ++stats_.records_retired;
    } else {
      if (kept_tags != r) tag_records_[kept_tags] = tag_records_[r];
      ++kept_tags;
    }
  }
  tag_records_.resize(kept_tags);
  CullKeyframes();
  RebuildRecordIndexes();
  retire_check_at_ = 2 * (slot_records_.size() + tag_records_.size());
}

void Mapper::CullKeyframes() {
  const int n = static_cast<int>(keyframes_.size());
  if (n == 0) return;
  // The window's keyframes and the fixed one before it stay, and the first
  // (the map's anchor), and every keyframe a record names.
  std::vector<bool> keep(static_cast<size_t>(n), false);
  keep[0] = true;
  for (int k = std::max(0, n - options_.window_keyframes - 1); k < n; ++k)
    keep[static_cast<size_t>(k)] = true;
  for (const SlotRecord& record : slot_records_) keep[static_cast<size_t>(record.keyframe)] = true;
  for (const TagRecord& record : tag_records_) keep[static_cast<size_t>(record.keyframe)] = true;

  // T_a_b = T_a_k T_k_b, and to first order, with e = (t, yaw) of a
  // relative pose as the odometry factor takes it:
  //   Sigma_a_b = J1 Sigma_a_k J1^T + J2 Sigma_k_b J2^T,
  //   J1 = [I  R(yaw_a_k) [-y_k_b, x_k_b]^T; 0 0 1],  J2 = [R(yaw_a_k) 0; 0 1].
  std::vector<int> new_index(static_cast<size_t>(n), -1);
  size_t kept = 0;  // compacted in place, as the records
  SE2 T_a_k;
  Eigen::Matrix3d sigma_a_k = Eigen::Matrix3d::Zero();
  for (int k = 0; k < n; ++k) {
    Keyframe keyframe = keyframes_[static_cast<size_t>(k)];
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
    keyframes_[kept++] = keyframe;
  }
  if (static_cast<int>(kept) == n) return;
  keyframes_.resize(kept);
  for (SlotRecord& record : slot_records_)
    record.keyframe = new_index[static_cast<size_t>(record.keyframe)];
  for (TagRecord& record : tag_records_)
    record.keyframe = new_index[static_cast<size_t>(record.keyframe)];
}

void Mapper::MaybeMergeOnline() {
  const int every = options_.online_merge_every_keyframes;
  if (!long_drive_ || every <= 0 || keyframes_.size() % static_cast<size_t>(every) != 0) return;
  const int merged_before = stats_.slots_merged;
  const bool pruned = PruneUnconfirmedSlots();
  MergeDuplicates();
  if (!pruned && stats_.slots_merged == merged_before) return;
  RecomputeSlotEvidence();
  RebuildRecordIndexes();
}

bool Mapper::PruneUnconfirmedSlots() {
  const int after = options_.prune_unconfirmed_after_keyframes;
  if (after <= 0) return false;
  // The last keyframe that saw each slot (records come in keyframe order).
  std::vector<int> last_seen(slots_.size(), -1);
  for (const SlotRecord& record : slot_records_) {
    for (int c : record.candidates) last_seen[static_cast<size_t>(c)] = record.keyframe;
  }
  const int before = static_cast<int>(keyframes_.size()) - after;
  std::vector<bool> prune(slots_.size(), false);
  bool any = false;
  for (size_t s = 0; s < slots_.size(); ++s) {
    const SlotLandmark& slot = slots_[s];
    if (slot.alive && slot.observations < options_.min_observations && last_seen[s] < before) {
      prune[s] = true;
      any = true;
    }
  }
  if (!any) return false;
  size_t kept = 0;
  for (SlotRecord& record : slot_records_) {
    std::vector<int> candidates;
    std::vector<double> weights;
    for (size_t i = 0; i < record.candidates.size(); ++i) {
      if (prune[static_cast<size_t>(record.candidates[i])]) continue;
      candidates.push_back(record.candidates[i]);
      weights.push_back(record.weights[i]);
    }
    if (candidates.empty()) continue;  // it only ever named pruned slots
    if (record.chosen >= 0 && prune[static_cast<size_t>(record.chosen)])
      record.chosen = candidates.front();
    record.candidates = std::move(candidates);
    record.weights = std::move(weights);
    SlotRecord& into = slot_records_[kept++];
    if (&into != &record) into = std::move(record);
  }
  slot_records_.resize(kept);  // in place, as in RetireOldRecords
  for (size_t s = 0; s < slots_.size(); ++s) {
    if (!prune[s]) continue;
    slots_[s].alive = false;
    ++stats_.slots_pruned;
  }
  return true;
}

void Mapper::RebuildRecordIndexes() {
  slot_record_index_.assign(slots_.size(), {});
  for (size_t r = 0; r < slot_records_.size(); ++r) {
    for (int c : slot_records_[r].candidates)
      slot_record_index_[static_cast<size_t>(c)].push_back(r);
  }
  tag_record_index_.assign(tags_.size(), {});
  for (size_t r = 0; r < tag_records_.size(); ++r) {
    tag_record_index_[static_cast<size_t>(tag_records_[r].tag)].push_back(r);
  }
}

void Mapper::MergeDuplicates() {
  const int n = static_cast<int>(slots_.size());
  std::vector<int> target(n);
  for (int s = 0; s < n; ++s) target[s] = s;
  for (int a = 0; a < n; ++a) {
    if (!slots_[a].alive) continue;
    for (int b = a + 1; b < n; ++b) {
      if (!slots_[b].alive) continue;
      if ((CornerOf(slots_[a], 0) - CornerOf(slots_[b], 0)).norm() > options_.merge_distance_m ||
          (CornerOf(slots_[a], 1) - CornerOf(slots_[b], 1)).norm() > options_.merge_distance_m) {
        continue;
      }
      // Keep the better-observed slot.
      const bool keep_a = slots_[a].observations >= slots_[b].observations;
      const int keep = keep_a ? a : b, drop = keep_a ? b : a;
      slots_[drop].alive = false;
      target[drop] = keep;
      // The dropped slot's retired evidence stays with the records' new slot.
      SlotLandmark& kept = slots_[keep];
      const SlotLandmark& dropped = slots_[drop];
      for (const auto& [id, votes] : dropped.retired_votes) kept.retired_votes[id] += votes;
      kept.retired_observations += dropped.retired_observations;
      for (int j = 0; j < kSlotCorners; ++j) {
        kept.retired_corner_observations[j] += dropped.retired_corner_observations[j];
      }
      ++stats_.slots_merged;
      if (drop == a) break;
    }
  }
  auto resolve = [&target](int s) {
    while (target[s] != s) s = target[s];
    return s;
  };
  for (SlotRecord& record : slot_records_) {
    std::vector<int> candidates;
    std::vector<double> weights;
    for (size_t i = 0; i < record.candidates.size(); ++i) {
      const int s = resolve(record.candidates[i]);
      const auto it = std::find(candidates.begin(), candidates.end(), s);
      if (it == candidates.end()) {
        candidates.push_back(s);
        weights.push_back(record.weights[i]);
      } else {
        double& w = weights[it - candidates.begin()];
        w = std::max(w, record.weights[i]);
      }
    }
    record.candidates = std::move(candidates);
    record.weights = std::move(weights);
    if (record.chosen >= 0) record.chosen = resolve(record.chosen);
  }
}

void Mapper::AssignIds() {
  struct Claim {
    double votes;
    int slot;
    std::string id;
  };
  std::vector<Claim> claims;
  for (int s = 0; s < static_cast<int>(slots_.size()); ++s) {
    SlotLandmark& slot = slots_[s];
    slot.id.clear();
    if (!slot.alive) continue;
    double total = 0.0;
    for (const auto& [id, votes] : slot.votes) total += votes;
    for (const auto& [id, votes] : slot.votes) {
      // A name needs enough agreeing readings and most of the slot's votes.
      if (votes >= options_.id_min_votes && votes > 0.5 * total) claims.push_back({votes, s, id});
    }
  }
  std::sort(claims.begin(), claims.end(), [](const Claim& a, const Claim& b) {
    return a.votes > b.votes || (a.votes == b.votes && a.slot < b.slot);
  });
  std::set<std::string> taken;
  for (const Claim& claim : claims) {
    SlotLandmark& slot = slots_[claim.slot];
    if (!slot.id.empty() || taken.count(claim.id) > 0) continue;
    slot.id = claim.id;
    taken.insert(claim.id);
  }
}

void Mapper::Finish() {
  const auto start = std::chrono::steady_clock::now();
  if (options_.mode == MappingMode::kBatch) {
    for (int round = 0; round < options_.final_rounds; ++round) {
      Solve(0, options_.final_iterations, true);
      RecomputeSlotEvidence();
      MergeDuplicates();
    }
  } else {
    RecomputeSlotEvidence();
    MergeDuplicates();
  }
  RecomputeSlotEvidence();
  AssignIds();
  stats_.final_solve_ms = ElapsedMs(start);
}

SemanticMap Mapper::Map() const {
  SemanticMap map;
  map.metadata["source"] = "parkslam mapper";
  map.metadata["robust"] = options_.robust == RobustMode::kMaxMixture ? "maxmix" : "none";
  map.metadata["mode"] = options_.mode == MappingMode::kBatch ? "batch" : "online";
  for (const SlotLandmark& slot : slots_) {
    if (!slot.alive || slot.observations < options_.min_observations) continue;
    MapSlot s;
    s.id = slot.id.empty() ? "t" + std::to_string(slot.temporary_number) : slot.id;
    s.temporary = slot.id.empty();
    if (std::abs(slot.angle_rad - kPi / 2) > 1e-6) {
      s.kind = SlotKind::kAngled;
    } else {
      s.kind = slot.width_m > 4.0 ? SlotKind::kParallel : SlotKind::kPerpendicular;
    }
    for (int j = 0; j < kSlotCorners; ++j) {
      s.corners_map[j] = CornerOf(slot, j);
      s.corner_observed[j] = slot.corner_observations[j] > 0;
      // Approximate: the detector's typical sigma over the evidence; guessed
      // corners rest on the shape constraint.
      s.corner_sigma_m[j] = s.corner_observed[j]
                                ? 0.05 / std::sqrt(static_cast<double>(slot.corner_observations[j]))
                                : options_.shape_length_sigma_m;
    }
    s.observation_count = slot.observations;
    map.slots.push_back(s);
  }
  // Each tag implies an obstacle: the face of the wall or pillar it hangs on,
  // drawn as a segment one metre wide behind it.
  for (const TagLandmark& tag : tags_) {
    const Eigen::Vector2d p(tag.pose[0], tag.pose[1]);
    const Eigen::Vector2d along(-std::sin(tag.pose[2]), std::cos(tag.pose[2]));
    map.obstacles.push_back({ObstacleKind::kWall, {p - 0.5 * along, p + 0.5 * along}});
    map.tags.push_back({tag.tag_id, p, tag.pose[2], options_.tag_size_m,
                        static_cast<int>(map.obstacles.size()) - 1});
  }
  return map;
}

Trajectory Mapper::KeyframeTrajectory() const {
  Trajectory trajectory;
  for (int k = 0; k < static_cast<int>(keyframes_.size()); ++k) {
    trajectory.push_back({keyframes_[k].t_ns, PoseOf(k)});
  }
  return trajectory;
}

}  // namespace parkslam::mapping
