#ifndef PARKSLAM_MAPPING_MAPPER_H_
#define PARKSLAM_MAPPING_MAPPER_H_

// The semantic mapper (paper III-C): keyframes from the Kalman dead
// reckoning, slot and tag landmarks, per-frame association by ID and nearest
// neighbour (association.h), a Ceres factor graph with the rectangular slot
// constraint and a Max-Mixture over ambiguous associations (map_graph.h),
// lazy slots with temporary IDs, ID votes, duplicate merging
// (slot_management.h). Online (a bounded windowed update per keyframe and
// the full graph solved in the background, background_solve.h) or batch (a
// full optimization at the end). This class makes the keyframes, bounds the
// memory of long drives and drives the parts.

#include <array>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "parkslam/common/trajectory.h"
#include "parkslam/map/semantic_map.h"
#include "parkslam/mapping/background_solve.h"
#include "parkslam/mapping/map_graph.h"
#include "parkslam/mapping/map_state.h"
#include "parkslam/mapping/mapper_options.h"
#include "parkslam/odometry/odometry_ekf.h"
#include "parkslam/sensor/sensor_data.h"

namespace parkslam::mapping {

struct MapperStats {
  int keyframes = 0;
  int slot_observations = 0;           // attached to keyframes
  int rejected_slot_observations = 0;  // malformed: not a plausible slot shape
  int mixture_observations = 0;        // with more than one component
  int slots_created = 0;
  int slots_merged = 0;
  int records_retired = 0;    // slot and tag records (MapperOptions::max_records_per_landmark)
  int slots_pruned = 0;       // unconfirmed (MapperOptions::prune_unconfirmed_after_keyframes)
  int slots_overlapping = 0;  // dropped at the end (MapperOptions::max_overlap_share)
  int keyframes_culled = 0;   // no record left to name them (Mapper::CullKeyframes)
  int tag_observations = 0;
  std::vector<double> keyframe_update_ms;  // per keyframe: association and update
  // The most residual blocks (odometry, observations, slot shapes) one
  // windowed (online) solve took: what bounds its time however long the
  // drive.
  int max_window_residual_blocks = 0;
  // Online: the full solves in the background (MapperOptions::
  // background_solve_every_s), each one's time in its thread, and how long
  // the foreground waited for them in all (with background_wait: a replay
  // that runs faster than the drive). The waits are not in
  // keyframe_update_ms.
  int background_solves = 0;
  std::vector<double> background_solve_ms;
  double background_wait_ms = 0.0;
  double final_solve_ms = 0.0;  // with the covariances
  double covariance_ms = 0.0;   // the corners' (MapperOptions::corner_sigma_from_graph)
  int final_iterations = 0;
  double final_cost = 0.0;
};

class Mapper {
 public:
  // initial_pose: the start pose in the map frame; without it the map frame
  // is the odometry frame (origin at the start, yaw of the first heading).
  Mapper(const MapperOptions& options, const odometry::OdometryEkfOptions& ekf_options,
         std::optional<SE2> initial_pose = std::nullopt);
  ~Mapper();
  Mapper(Mapper&&) noexcept;
  Mapper& operator=(Mapper&&) noexcept;

  // Feeds one event of the time-ordered sensor stream.
  void Process(const SensorEvent& event);

  // Ends the session: the final optimization (batch), duplicate merging and
  // ID assignment.
  void Finish();

  SemanticMap Map() const;
  // The map as it stands, with the slots seen at least min_observations
  // times (Map: MapperOptions::min_observations). Along the drive, before
  // Finish, the slots carry the IDs their votes would give them if the
  // drive ended there.
  SemanticMap Map(int min_observations) const;
  // For comparison along the drive: the map that ending the drive here in
  // batch would give (Finish's final solves on a copy of the state, no
  // corner covariances). Costs a full solve.
  SemanticMap BatchMapSoFar(int min_observations) const;
  // The car's pose at the newest event: the newest keyframe's, as the graph
  // has it, moved on by the dead reckoning since; identity before the
  // first keyframe. And the time it is at.
  SE2 CurrentPose() const;
  TimeNs current_time_ns() const { return ekf_->time_ns(); }
  // The keyframes' poses. On a long drive (MapperOptions::
  // retire_check_min_records) keyframes that no kept record names are
  // culled, so the trajectory there is sparser.
  Trajectory KeyframeTrajectory() const;
  const MapperStats& stats() const { return stats_; }
  // What the dead reckoning saw of its inputs' faults (late events, gated
  // spikes, sensor gaps).
  const odometry::OdometryEkfStats& odometry_stats() const { return ekf_->stats(); }

  // The state the parts work on (map_state.h), for tests.
  const MapState& state() const { return state_; }
  const std::deque<Keyframe>& keyframes() const { return state_.keyframes; }
  const std::deque<SlotLandmark>& slots() const { return state_.slots; }
  const std::vector<SlotRecord>& slot_records() const { return state_.slot_records; }
  const std::vector<TagRecord>& tag_records() const { return state_.tag_records; }

 private:
  static SemanticMap MapOf(const MapState& state, const MapperOptions& options,
                           const CornerCovariances& corner_covariances, int min_observations,
                           const std::vector<std::string>& ids);
  bool MaybeAddKeyframe(TimeNs t_ns, bool has_observations);
  // Association (association.h), then slot management (a new slot, or the
  // record and its evidence).
  void AddSlotObservation(int keyframe, const SlotObservation& observation);
  void AddTag(int keyframe, const TagObservation& observation);
  // A windowed solve of the graph (map_graph.h), then the records' new
  // choices, their evidence moved one by one.
  void Solve(int first_free_keyframe, int max_iterations);
  // Retires each landmark's records beyond MapperOptions::
  // max_records_per_landmark (every second one outside the window) and
  // compacts the storage; runs when the records have doubled since.
  void RetireOldRecords();
  // Drops the keyframes before the window that no record names any more,
  // folding their odometry into the next keyframe's (the relative poses
  // compounded, their covariances propagated): the same chain of
  // constraints, one factor shorter.
  void CullKeyframes();
  // MapperOptions::online_merge_every_keyframes and
  // prune_unconfirmed_after_keyframes, and the merge after a background
  // solve.
  void MaybeMergeOnline();
  void AfterKeyframe();
  // Online (MapperOptions::background_solve_every_s): lays the background
  // solve into the state once it is due (or done), and starts the next
  // after the upkeep that waits for it. Return how long they waited for the
  // solve, ms.
  double MaybeApplyBackgroundSolve(TimeNs t_ns);
  void MaybeStartBackgroundSolve(TimeNs t_ns);
  double ApplyBackgroundSolve();
  bool BackgroundRunning() const;

  MapperOptions options_;
  std::unique_ptr<odometry::OdometryEkf> ekf_;
  std::optional<SE2> initial_pose_;
  MapState state_;
  size_t retire_check_at_ = 0;  // records stored when RetireOldRecords next looks
  bool long_drive_ = false;     // retire_check_min_records were stored once
  double distance_since_solve_m_ = 0.0;
  bool finished_ = false;  // Finish named the slots
  // MaybeMergeOnline's work, deferred while a background solve runs: the
  // long drive's pruning and merging, and a merge after each background
  // solve.
  bool prune_pending_ = false;
  bool merge_pending_ = false;
  std::unique_ptr<BackgroundSolve> background_;  // online with background_solve_every_s
  TimeNs background_due_ns_ = 0;
  // The records, keyframes or slots were restructured since the background
  // solve's mirror was last brought in step: it is rebuilt whole.
  bool mirror_stale_ = true;
  MapperStats stats_;
  // The corners' marginal covariances at the end (Finish), by slot index;
  // empty when the graph's could not be computed.
  CornerCovariances corner_covariances_;
};

}  // namespace parkslam::mapping

#endif  // PARKSLAM_MAPPING_MAPPER_H_
