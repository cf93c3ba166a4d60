#ifndef PARKSLAM_LOCALIZATION_LOCALIZER_H_
#define PARKSLAM_LOCALIZATION_LOCALIZER_H_

// Map-based localization (paper IV-B): the car's pose in a map built before,
// at every camera frame. Prediction from the Kalman dead reckoning's motion
// between frames; updates from slot corners and tags associated by ID and by
// gated nearest neighbour, each checked by a chi-square test so that a
// misread ID cannot pull the pose; global (re)localization from confidently
// read slot IDs and tags, confirmed by the geometry of the last seconds.

#include <Eigen/Core>
#include <cmath>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "parkslam/common/se2.h"
#include "parkslam/map/semantic_map.h"
#include "parkslam/odometry/odometry_ekf.h"
#include "parkslam/sensor/sensor_data.h"

namespace parkslam::localization {

struct LocalizerOptions {
  // Measurement noise floors (the detector reports its own sigma).
  double corner_sigma_floor_m = 0.03;
  double map_corner_sigma_floor_m = 0.005;
  double tag_map_sigma_m = 0.03;
  double tag_map_yaw_sigma_rad = 0.02;
  // The map's own error, which no number of sightings averages away (every
  // sighting of a landmark sees the same map error): the filter estimates
  // the pose against the map's landmarks, and the covariance it reports adds
  // the map's stated uncertainty where it last anchored the pose, the
  // variance of the landmarks last used (slot entrance corners: the map's
  // corner_sigma_m, at least map_corner_sigma_floor_m; tags:
  // tag_map_sigma_m) on x and y and map_yaw_sigma_rad on yaw
  // (docs/localization.md, "Consistency").
  double map_yaw_sigma_rad = 0.0005;
  // The wheel speed's scale error, estimated beside the pose: it is off by
  // a fraction that stays for the drive (tyre radius, load, pressure), so
  // every frame's motion is off by the same fraction, an error that no
  // frame-by-frame motion covariance carries (it would average away as
  // white noise). Its prior is the odometry's wheel_scale_sigma; it may
  // wander by wheel_scale_walk_per_sqrt_m. false: the odometry's distances
  // taken as they come.
  bool estimate_wheel_scale = true;
  double wheel_scale_walk_per_sqrt_m = 5e-5;
  // Association: a reading of at least this confidence names its slot; other
  // observations go to the nearest map slot within nn_radius_m. Every update
  // must pass the chi-square gate at gate_probability.
  double id_min_confidence = 0.5;
  double nn_radius_m = 1.5;
  double gate_probability = 0.999;
  // Lost: within the last lost_after_s at least lost_min_rejected
  // observations were rejected and none accepted (driving where nothing is
  // seen is dead reckoning, not lost), or the position uncertainty grew
  // above lost_position_sigma_m.
  double lost_after_s = 1.0;
  int lost_min_rejected = 5;
  double lost_position_sigma_m = 1.5;
  // Global (re)localization over the frames of the last reloc_window_s.
  double reloc_window_s = 2.0;
  double reloc_inlier_m = 0.4;
  int reloc_min_inliers = 6;
  int reloc_min_landmarks = 3;
  double reloc_ambiguity_ratio = 0.7;  // a rival this close in support: wait
  double reloc_position_sigma_m = 0.3;
  double reloc_yaw_sigma_rad = 0.05;
  // A start at the map's entrance (`--init entrance`): the car is in the
  // entrance lane, heading along it within about 2 degrees. The heading's
  // sigma carries the pose across a corridor without landmarks (0.03 rad
  // is 1.2 m to the side after 40 m), where --init's 0.1 rad would be 4 m.
  double entrance_position_sigma_m = 0.5;
  double entrance_yaw_sigma_rad = 0.03;
  Eigen::Vector3d EntranceSigmas() const {
    return {entrance_position_sigma_m, entrance_position_sigma_m, entrance_yaw_sigma_rad};
  }

  bool IsValid(std::string* error) const;

  // The field list, walked by the options file reader (io/options_yaml.h).
  template <typename V>
  void VisitFields(V& v) {
    v("corner_sigma_floor_m", corner_sigma_floor_m);
    v("map_corner_sigma_floor_m", map_corner_sigma_floor_m);
    v("tag_map_sigma_m", tag_map_sigma_m);
    v("tag_map_yaw_sigma_rad", tag_map_yaw_sigma_rad);
    v("map_yaw_sigma_rad", map_yaw_sigma_rad);
    v("estimate_wheel_scale", estimate_wheel_scale);
    v("wheel_scale_walk_per_sqrt_m", wheel_scale_walk_per_sqrt_m);
    v("id_min_confidence", id_min_confidence);
    v("nn_radius_m", nn_radius_m);
    v("gate_probability", gate_probability);
    v("lost_after_s", lost_after_s);
    v("lost_min_rejected", lost_min_rejected);
    v("lost_position_sigma_m", lost_position_sigma_m);
    v("reloc_window_s", reloc_window_s);
    v("reloc_inlier_m", reloc_inlier_m);
    v("reloc_min_inliers", reloc_min_inliers);
    v("reloc_min_landmarks", reloc_min_landmarks);
    v("reloc_ambiguity_ratio", reloc_ambiguity_ratio);
    v("reloc_position_sigma_m", reloc_position_sigma_m);
    v("reloc_yaw_sigma_rad", reloc_yaw_sigma_rad);
    v("entrance_position_sigma_m", entrance_position_sigma_m);
    v("entrance_yaw_sigma_rad", entrance_yaw_sigma_rad);
  }
};

enum class LocalizerState { kUninitialized, kTracking, kLost };
const char* ToString(LocalizerState state);

// What became of one landmark class's observations (slots or tags): every
// observation the front end made is counted once, in exactly one of
// `used`, `rejected_no_map_landmark`, `rejected_gate` and `while_lost`, so
// that a class silently lost between the front end and the localizer shows.
struct LandmarkUse {
  int observed = 0;    // observations made
  int associated = 0;  // with at least one map candidate (by ID or near)
  int used = 0;        // updated the pose
  // Slots: no confident ID in the map and no map slot within nn_radius_m;
  // tags: a tag ID the map does not have.
  int rejected_no_map_landmark = 0;
  int rejected_gate = 0;  // every candidate failed the chi-square gate
  int while_lost = 0;     // seen while uninitialized or lost (relocalization only)

  int rejected() const { return rejected_no_map_landmark + rejected_gate; }
  LandmarkUse& operator+=(const LandmarkUse& other);
};

struct LocalizationEstimate {
  TimeNs t_ns = 0;
  SE2 T_map_vehicle;
  // Of the pose in the lot: the filter's covariance against the map's
  // landmarks plus the map's own error where it last anchored the pose.
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  LocalizerState state = LocalizerState::kUninitialized;
  LandmarkUse slots;
  LandmarkUse tags;
  bool relocalized = false;

  int used() const { return slots.used + tags.used; }
  int rejected() const { return slots.rejected() + tags.rejected(); }
};

class Localizer {
 public:
  Localizer(const SemanticMap& map, const LocalizerOptions& options,
            const odometry::OdometryEkfOptions& odometry_options);
  ~Localizer();
  Localizer(Localizer&&) noexcept;
  Localizer& operator=(Localizer&&) noexcept;

  // A known start pose (`--init`); without one the localizer starts
  // uninitialized and localizes globally.
  void SetPose(const SE2& T_map_vehicle, const Eigen::Matrix3d& covariance);

  // Feeds one event; returns an estimate at every camera frame (slot or
  // tag frame), nothing otherwise.
  std::optional<LocalizationEstimate> Process(const SensorEvent& event);

  LocalizerState state() const { return state_; }
  // What the dead reckoning saw of its inputs' faults.
  const odometry::OdometryEkfStats& odometry_stats() const { return odometry_->stats(); }
  // The pose at the last camera frame.
  SE2 pose() const { return SE2(x_[0], x_[1], x_[2]); }
  // The pose now: the last estimate moved on by the odometry since that
  // frame (for a controller running faster than the cameras).
  SE2 PredictedPose() const;
  // The filter's covariance of the pose, against the map's landmarks
  // (without the map's own error that LocalizationEstimate::covariance adds).
  Eigen::Matrix3d covariance() const { return P_.topLeftCorner<3, 3>(); }
  // The wheel speed's scale error as estimated (a fraction: 0.01 reads 1 %
  // too fast) and its standard deviation.
  double wheel_scale_error() const { return x_[kScale]; }
  double wheel_scale_sigma() const { return std::sqrt(P_(kScale, kScale)); }
  // The pose and that covariance at the camera frame of time t_ns, while
  // tracking and when that frame was the last one in; nothing otherwise.
  // For a front end that looks for the frame's tags where the map has them
  // (perception::TagWindowOptions).
  std::optional<std::pair<SE2, Eigen::Matrix3d>> TrackedAt(TimeNs t_ns) const;
  const SemanticMap& map() const { return map_; }

 private:
  struct BufferedFrame {
    TimeNs t_ns = 0;
    SE2 T_odom_vehicle;
    std::vector<SlotObservation> slots;
    std::vector<TagObservation> tags;
  };

  void Predict(const odometry::OdometryEkf::RelativeMotion& motion);
  // By how much the odometry's distance is to be multiplied: its own
  // estimate of the wheel scale error against ours.
  double DistanceFactor() const;
  // EKF update with a stacked measurement; false when the gate rejects it.
  template <int N>
  bool Update(const Eigen::Matrix<double, N, 1>& innovation,
              const Eigen::Matrix<double, N, 3>& H_pose, const Eigen::Matrix<double, N, N>& R);
  // Each updates the pose with the observation where it can and adds the
  // outcome to `use`; returns the map's position variance at the landmark
  // that updated the pose, nothing when none did.
  std::optional<double> UpdateSlot(const SlotObservation& observation, LandmarkUse* use);
  std::optional<double> UpdateTag(const TagObservation& observation, LandmarkUse* use);
  bool TryRelocalize(TimeNs t_ns);
  // Observations of the buffered frames that land on the map under the
  // hypothesis T_map_now: their count, the landmarks they hit, and the
  // point pairs (in the current vehicle frame, in the map); and those that
  // land on a slot other than the one their confident ID names.
  struct Support {
    int inliers = 0;
    int conflicts = 0;
    int score() const { return inliers - conflicts; }
    std::vector<int> landmarks;
    std::vector<Eigen::Vector2d> points_now, points_map;
  };
  Support CountInliers(const SE2& T_map_now) const;

  SemanticMap map_;
  LocalizerOptions options_;
  std::unique_ptr<odometry::OdometryEkf> odometry_;
  std::map<std::string, int> slot_by_id_;
  std::map<int, int> tag_by_id_;
  LocalizerState state_ = LocalizerState::kUninitialized;
  // State [x_m, y_m, yaw_rad, wheel_scale_error]: the pose in the map and
  // the fraction by which the wheel speed overstates the speed.
  static constexpr int kScale = 3;
  using State = Eigen::Vector4d;
  using StateCovariance = Eigen::Matrix4d;
  State x_ = State::Zero();
  StateCovariance P_ = StateCovariance::Identity();
  // Association outcomes of the last lost_after_s: time and accepted.
  std::deque<std::pair<TimeNs, bool>> recent_outcomes_;
  TimeNs last_frame_ns_ = 0;
  // The map's position variance where the pose was last anchored (0: not
  // yet): its mean over the landmarks of the last frame that used any.
  double map_position_var_ = 0.0;
  std::deque<BufferedFrame> buffer_;
  double gate_chi2_[5] = {0, 0, 0, 0, 0};  // by measurement dimension
};

}  // namespace parkslam::localization

#endif  // PARKSLAM_LOCALIZATION_LOCALIZER_H_
