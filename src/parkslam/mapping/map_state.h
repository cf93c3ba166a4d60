#ifndef PARKSLAM_MAPPING_MAP_STATE_H_
#define PARKSLAM_MAPPING_MAP_STATE_H_

// What the mapper knows while it maps: keyframes, slot and tag landmarks,
// and the records of the observations that tie them together. The parts
// of the mapper work on it: association (association.h) reads it, slot
// management (slot_management.h) keeps the slots, their evidence and IDs,
// the graph (map_graph.h) builds, solves and reads back the factor graph
// over it, and the Mapper (mapper.h) makes keyframes and drives the rest.

#include <Eigen/Core>
#include <array>
#include <deque>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "parkslam/common/se2.h"
#include "parkslam/common/time.h"
#include "parkslam/map/semantic_map.h"
#include "parkslam/sensor/sensor_data.h"

namespace parkslam::mapping {

struct Keyframe {
  TimeNs t_ns = 0;
  std::array<double, 3> pose{};  // x_m, y_m, yaw_rad in the map frame
  SE2 T_previous_this;           // odometry since the previous keyframe
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  // The dead reckoning's own estimate of the wheel speed's scale error when
  // it reached this keyframe (it learns it in turns): what T_previous_this
  // was measured with (OdometryFactor).
  double odometry_wheel_scale = 0.0;
};

struct SlotLandmark {
  std::array<std::array<double, 2>, kSlotCorners> corners{};  // map frame, m
  // The rectangular constraint's shape (paper III-A), from the first
  // observation.
  double angle_rad = 0.0, width_m = 0.0, depth_m = 0.0;
  int temporary_number = 0;  // "t12"
  bool alive = true;         // false: merged into another, or pruned
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

  Eigen::Vector2d Corner(int j) const { return {corners[j][0], corners[j][1]}; }
};

struct TagLandmark {
  int tag_id = 0;
  std::array<double, 3> pose{};  // x_m, y_m, yaw_rad in the map frame
  int observations = 0;
};

// A slot observation and the slots it may be (Max-Mixture components,
// paper III-C), with the weight of each, whether a null hypothesis
// (an outlier) is one of them, and the one chosen now.
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

struct MapState {
  std::deque<Keyframe> keyframes;
  std::deque<SlotLandmark> slots;
  std::deque<TagLandmark> tags;
  std::map<int, int> tag_index;  // tag ID -> index
  std::vector<SlotRecord> slot_records;
  std::vector<TagRecord> tag_records;
  // Per slot (tag): the indices of the records that name it as a candidate
  // (observe it), oldest first, for windowed solves that stay bounded. Not
  // updated by the final merge, after which no windowed solve runs.
  std::vector<std::vector<size_t>> slot_record_index, tag_record_index;
  // The slot currently holding most votes for each ID, and those votes.
  std::map<std::string, std::pair<int, double>> id_owner;
  int next_temporary_number = 1;
  // The wheel speed's scale error, one unknown of the graph shared by every
  // odometry factor (a fraction: 0.003 reads 0.3 % too fast), with its
  // prior's sigma; a sigma of 0 holds it at 0.
  std::array<double, 1> wheel_scale_error{};
  double wheel_scale_sigma = 0.0;

  SE2 PoseOf(int keyframe) const {
    const std::array<double, 3>& p = keyframes[static_cast<size_t>(keyframe)].pose;
    return SE2(p[0], p[1], p[2]);
  }
  // Rebuilds both record indexes from the records.
  void RebuildRecordIndexes();
};

}  // namespace parkslam::mapping

#endif  // PARKSLAM_MAPPING_MAP_STATE_H_
