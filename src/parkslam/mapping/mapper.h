#ifndef PARKSLAM_MAPPING_MAPPER_H_
#define PARKSLAM_MAPPING_MAPPER_H_

// The semantic mapper (paper III-C): keyframes from the Kalman dead
// reckoning, slot and tag landmarks, per-frame association by ID and nearest
// neighbour (association.h), a Ceres factor graph with the rectangular slot
// constraint and a Max-Mixture over ambiguous associations (map_graph.h),
// lazy slots with temporary IDs, ID votes, duplicate merging
// (slot_management.h). Online (a bounded windowed update per keyframe) or
// batch (a full optimization at the end). This class makes the keyframes,
// bounds the memory of long drives and drives the parts.

#include <array>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "parkslam/common/trajectory.h"
#include "parkslam/map/semantic_map.h"
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
  bool MaybeAddKeyframe(TimeNs t_ns, bool has_observations);
  // Association (association.h), then slot management (a new slot, or the
  // record and its evidence).
  void AddSlotObservation(int keyframe, const SlotObservation& observation);
  void AddTag(int keyframe, const TagObservation& observation);
  // The graph (map_graph.h), then the records' new choices: their evidence
  // moved one by one after a windowed solve, all recounted after the final.
  void Solve(int first_free_keyframe, int max_iterations, bool final);
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
  // prune_unconfirmed_after_keyframes.
  void MaybeMergeOnline();
  void AfterKeyframe();

  MapperOptions options_;
  std::unique_ptr<odometry::OdometryEkf> ekf_;
  std::optional<SE2> initial_pose_;
  MapState state_;
  size_t retire_check_at_ = 0;  // records stored when RetireOldRecords next looks
  bool long_drive_ = false;     // retire_check_min_records were stored once
  double distance_since_solve_m_ = 0.0;
  MapperStats stats_;
  // The corners' marginal covariances at the end (Finish), by slot index;
  // empty when the graph's could not be computed.
  CornerCovariances corner_covariances_;
};

}  // namespace parkslam::mapping

#endif  // PARKSLAM_MAPPING_MAPPER_H_
