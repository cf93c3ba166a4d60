#ifndef PARKSLAM_MAPPING_MAPPER_H_
#define PARKSLAM_MAPPING_MAPPER_H_

// The semantic mapper (paper III-C): keyframes from the Kalman dead
// reckoning, slot and tag landmarks, per-frame association by ID and nearest
// neighbour, a Ceres factor graph with the rectangular slot constraint and a
// Max-Mixture over ambiguous associations, lazy slots with temporary IDs,
// ID votes, duplicate merging. Online (a bounded windowed update per
// keyframe) or batch (a full optimization at the end).

#include <array>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "parkslam/common/trajectory.h"
#include "parkslam/map/semantic_map.h"
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
  int records_retired = 0;   // slot and tag records (MapperOptions::max_records_per_landmark)
  int slots_pruned = 0;      // unconfirmed (MapperOptions::prune_unconfirmed_after_keyframes)
  int keyframes_culled = 0;  // no record left to name them (Mapper::CullKeyframes)
  int tag_observations = 0;
  std::vector<double> keyframe_update_ms;  // per keyframe: association and update
  // The most residual blocks (odometry, observations, slot shapes) one
  // windowed (online) solve took: what bounds its time however long the
  // drive.
  int max_window_residual_blocks = 0;
  double final_solve_ms = 0.0;
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

  // Internals, public for tests.
  struct Keyframe {
    TimeNs t_ns = 0;
    std::array<double, 3> pose{};  // x_m, y_m, yaw_rad in the map frame
    SE2 T_previous_this;           // odometry since the previous keyframe
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  };
  struct SlotLandmark {
    std::array<std::array<double, 2>, kSlotCorners> corners{};
    double angle_rad = 0.0, width_m = 0.0, depth_m = 0.0;
    int temporary_number = 0;
    bool alive = true;
    // Derived from the observations that chose it.
    std::map<std::string, double> votes;
    int observations = 0;
    std::array<int, kSlotCorners> corner_observations{};
    std::string id;  // empty: temporary
    // What retired records said of it (MapperOptions::
    // max_records_per_landmark), kept when the evidence is recounted.
    std::map<std::string, double> retired_votes;
    int retired_observations = 0;
    std::array<int, kSlotCorners> retired_corner_observations{};
  };
  struct TagLandmark {
    int tag_id = 0;
    std::array<double, 3> pose{};
    int observations = 0;
  };
  struct SlotRecord {
    int keyframe = 0;
    SlotObservation observation;
    std::vector<int> candidates;  // slot indices
    std::vector<double> weights;
    bool has_null = false;
    int chosen = -1;  // slot index, -1: null
  };
  struct TagRecord {
    int keyframe = 0;
    TagObservation observation;
    int tag = 0;  // index into tags
  };

  const std::deque<Keyframe>& keyframes() const { return keyframes_; }
  const std::deque<SlotLandmark>& slots() const { return slots_; }
  const std::vector<SlotRecord>& slot_records() const { return slot_records_; }
  const std::vector<TagRecord>& tag_records() const { return tag_records_; }

 private:
  bool MaybeAddKeyframe(TimeNs t_ns, bool has_observations);
  SE2 PoseOf(int keyframe) const;
  void AssociateSlot(int keyframe, const SlotObservation& observation);
  int CreateSlot(int keyframe, const SlotObservation& observation);
  void AddTag(int keyframe, const TagObservation& observation);
  double IdSupport(const SlotLandmark& slot, const SlotObservation& observation) const;
  void UpdateIdOwner(int slot);
  void Solve(int first_free_keyframe, int max_iterations, bool final);
  void RecomputeSlotEvidence();
  // Adds (sign +1) or removes (-1) what one record says of slot_index
  // (observation count, corners seen, ID votes); nothing for slot -1.
  void MoveEvidence(const SlotRecord& record, int slot_index, int sign);
  // The same, to any tallies: a slot's own, or what its retired records said.
  void AddEvidence(const SlotRecord& record, int sign, std::map<std::string, double>* votes,
                   int* observations, std::array<int, kSlotCorners>* corner_observations) const;
  // The owner of each ID from the alive slots' votes.
  void RebuildIdOwners();
  // Files the record about to be appended under each of its candidates.
  void IndexSlotRecord(const SlotRecord& record);
  // Retires each landmark's records beyond MapperOptions::
  // max_records_per_landmark (oldest first, never the window's) and
  // compacts the storage; runs when the records have doubled since.
  void RetireOldRecords();
  void RebuildRecordIndexes();
  // Drops the keyframes before the window that no record names any more,
  // folding their odometry into the next keyframe's (the relative poses
  // compounded, their covariances propagated): the same chain of
  // constraints, one factor shorter.
  void CullKeyframes();
  // MapperOptions::online_merge_every_keyframes and
  // prune_unconfirmed_after_keyframes.
  void MaybeMergeOnline();
  // Drops the unconfirmed slots of long ago and their records; true if any.
  bool PruneUnconfirmedSlots();
  void MergeDuplicates();
  void AssignIds();
  void AfterKeyframe();

  MapperOptions options_;
  std::unique_ptr<odometry::OdometryEkf> ekf_;
  std::optional<SE2> initial_pose_;
  std::deque<Keyframe> keyframes_;
  std::deque<SlotLandmark> slots_;
  std::deque<TagLandmark> tags_;
  std::map<int, int> tag_index_;  // tag ID -> index
  std::vector<SlotRecord> slot_records_;
  std::vector<TagRecord> tag_records_;
  // Per slot (tag): the indices of the records that name it as a candidate
  // (observe it), oldest first, for windowed solves that stay bounded. Not
  // updated by the final merge, after which no windowed solve runs.
  std::vector<std::vector<size_t>> slot_record_index_, tag_record_index_;
  // The slot currently holding most votes for each ID, and those votes.
  std::map<std::string, std::pair<int, double>> id_owner_;
  size_t retire_check_at_ = 0;  // records stored when RetireOldRecords next looks
  bool long_drive_ = false;     // retire_check_min_records were stored once
  double distance_since_solve_m_ = 0.0;
  int next_temporary_number_ = 1;
  MapperStats stats_;
};

}  // namespace parkslam::mapping

#endif  // PARKSLAM_MAPPING_MAPPER_H_
