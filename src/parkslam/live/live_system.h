#ifndef PARKSLAM_LIVE_LIVE_SYSTEM_H_
#define PARKSLAM_LIVE_LIVE_SYSTEM_H_

// The system live on a car (docs/library.md, "The live API"): one object
// that the car's software feeds with its messages as they arrive (camera
// frame sets, or slot and tag frames of its own detector; IMU, wheel speed,
// steering) and that gives the pose at every camera frame, a predicted pose
// at the newest odometry, and in mapping mode the map as it stands.
//
// The perception (paper III-A, III-B) runs in a thread of its own, so that
// odometry is never held up by it. The estimator (the localizer, or the
// mapper) must still see every event in time order, a camera frame's slots
// and tags at the frame's time and before the odometry after it: the
// odometry that arrives while a frame is being perceived waits in a queue
// until its slots and tags are in, then follows them. The prediction does
// not wait: a dead reckoning of its own takes every odometry event at once
// and carries the last estimate forward. When frames come faster than the
// perception, a frame still waiting for it when the next one arrives is
// dropped (and counted); the one being perceived is finished.
//
// Late, duplicate and out-of-order messages go to the estimator as they
// would from a recording (docs/robustness.md): its dead reckoning rejects
// what is older than itself.

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "parkslam/camera/camera_model.h"
#include "parkslam/common/se2.h"
#include "parkslam/common/trajectory.h"
#include "parkslam/localization/localizer.h"
#include "parkslam/map/semantic_map.h"
#include "parkslam/mapping/mapper.h"
#include "parkslam/odometry/odometry_ekf.h"
#include "parkslam/perception/camera_health.h"
#include "parkslam/perception/front_end.h"
#include "parkslam/sensor/sensor_data.h"

namespace parkslam::live {

struct LiveOptions {
  perception::PerceptionOptions perception;
  localization::LocalizerOptions localizer;
  // Mapping runs online (MapperOptions::mode is set so), its full solve in
  // the background without waiting for it (background_wait false) unless
  // wait_for_perception asks for a replay's determinism.
  mapping::MapperOptions mapper;
  odometry::OdometryEkfOptions odometry;
  // A replay that must give a recording's poses exactly (and the same on
  // every run): Process waits for each camera frame's perception, so no
  // frame is dropped, and the mapper's background solve waits as in `map`.
  // A car: false.
  bool wait_for_perception = false;
  // Odometry waits this long (of its own time, behind the newest odometry)
  // before it goes to the estimator, unless a camera frame after it needs
  // it, so that a camera frame set that arrives up to this late (its last
  // camera's image after odometry newer than its time, as separate
  // transports deliver them) still goes in in time order; the prediction
  // takes every odometry event at once. 0: each event in arrival order.
  double reorder_window_s = 0.0;
  // Localizing: called with each estimate the moment it is made, from the
  // thread that made it (the caller's, or the perception's), with the
  // system's lock held: it must be quick and must not call the system.
  // When set, the estimates go to it alone, and TakeEstimates gives none.
  std::function<void(const localization::LocalizationEstimate&)> on_estimate;
};

struct LiveStats {
  int camera_frames = 0;     // camera frame sets received
  int frames_perceived = 0;  // their slots and tags reached the estimator
  int frames_dropped = 0;    // still waiting when a newer frame came
  int estimates = 0;
  // Frames whose tags were looked for only in windows around the map's
  // tags (MapTagWindows), not in the whole band.
  int tag_searches_in_windows = 0;
  // Per camera frame: from the Process call that brought it to its first
  // pose (its slots': the top view's perception, the queue and the
  // estimator), ms; and to its second (its tags' too). Per slot or tag
  // frame given: from its Process call to its pose.
  std::vector<double> latency_ms;
  std::vector<double> complete_latency_ms;
  // Per frame perceived: the perception thread's time on it (the cameras'
  // health and the front end), ms.
  std::vector<double> perception_ms;
};

// Where `front_end` looks for the tags of the camera frame at t_ns, once
// `localizer` has taken that frame's slots: while it tracks, the windows
// around its map's tags as that pose puts them
// (perception::TagWindowOptions); else nothing, the whole band. LiveSystem
// does so, and harness::SensorStream for `localize`'s chain on pixels.
std::optional<std::vector<perception::TagWindow>> MapTagWindows(
    const perception::PerceptionFrontEnd& front_end, const localization::Localizer& localizer,
    TimeNs t_ns);

class LiveSystem {
 public:
  // Localizes on `map`; initial_pose: a start known to about
  // initial_sigma (x_m, y_m, yaw_rad; `localize --init`'s), else the
  // localizer localizes globally. `rig` (needed for camera frames) must
  // outlive the object; null when only slot and tag frames will come.
  LiveSystem(const SemanticMap& map, const camera::CameraRig* rig, const LiveOptions& options,
             std::optional<SE2> initial_pose = std::nullopt,
             const Eigen::Vector3d& initial_sigma = Eigen::Vector3d(0.5, 0.5, 0.1));
  // Maps; initial_pose as for mapping::Mapper.
  LiveSystem(const camera::CameraRig* rig, const LiveOptions& options,
             std::optional<SE2> initial_pose = std::nullopt);
  ~LiveSystem();
  LiveSystem(const LiveSystem&) = delete;
  LiveSystem& operator=(const LiveSystem&) = delete;

  // One message, in arrival order. Throws std::invalid_argument for a
  // camera frame without a rig, and what the estimator throws.
  void Process(SensorEvent event);
  // The estimates made since the last call, in time order (localizing).
  std::vector<localization::LocalizationEstimate> TakeEstimates();
  // The pose at the newest odometry: the last estimate (localizing) or the
  // mapper's newest keyframe (mapping), moved on by the dead reckoning
  // since, at the newest odometry's time; nothing before the first.
  std::optional<TimedPose> PredictedPose() const;
  // Mapping: the map as it stands (Finish: the final one). Localizing: the
  // map it localizes on.
  SemanticMap Map() const;
  // Mapping: the keyframes' poses as they stand (what mapping::UpdateMap
  // takes with the map); localizing: none.
  Trajectory KeyframeTrajectory() const;
  // Ends the drive: waits for the perception of the frames received, feeds
  // what they found, and (mapping) finishes the map.
  void Finish();

  LiveStats stats() const;
  bool mapping() const { return mapper_ != nullptr; }

 private:
  using Clock = std::chrono::steady_clock;
  // An event waiting for the estimator, or the place of a camera frame
  // whose slots and tags are not in yet.
  struct Pending {
    std::optional<SensorEvent> event;
    std::uint64_t frame = 0;  // the camera frame's number when a place
    Clock::time_point arrived;
    bool perceived = false;  // found in a camera frame by the perception
    TimeNs t_ns = 0;         // the event's time, or the camera frame's
  };
  struct Common {};  // the part both constructors share
  LiveSystem(Common, const camera::CameraRig* rig, const LiveOptions& options);
  void StartPerception();
  void PerceptionLoop();
  // What the perception found of a frame (its slot frame, then its tag
  // frame) goes in before its place, which goes with the last (or with
  // nothing: a dropped frame); then Drain. Under state_mutex_.
  void Resolve(std::uint64_t frame, std::optional<SensorEvent> event, bool keep_place);
  // Feeds the estimator what is ready from the front of the queue. Under
  // state_mutex_, as everything below it.
  void Drain();
  // Whether the pending event may go to the estimator now (reorder_window_s).
  bool Ready(std::deque<Pending>::const_iterator it) const;
  // Where an event of time t_ns goes in the queue (reorder_window_s):
  // before what waits there that is newer than it.
  std::deque<Pending>::iterator PlaceFor(TimeNs t_ns);
  void Feed(const SensorEvent& event, const Pending& from);
  // Drops the dead reckoning's poses older than the estimator's newest but
  // the last one before it.
  void PruneAheadTrack();
  void WaitForFrame(std::uint64_t frame);
  void RethrowPerceptionError();

  LiveOptions options_;
  const camera::CameraRig* rig_;

  // The estimator and its queue, under state_mutex_: the caller's thread
  // feeds them, and the perception thread drains the queue the moment a
  // frame is perceived, so that its pose is ready then.
  mutable std::mutex state_mutex_;
  std::unique_ptr<localization::Localizer> localizer_;
  std::unique_ptr<mapping::Mapper> mapper_;
  SemanticMap map_;  // localizing
  // The prediction's dead reckoning, every odometry event at once, and its
  // poses since the estimator's newest (oldest first).
  odometry::OdometryEkf ahead_;
  std::deque<std::pair<TimeNs, SE2>> ahead_track_;
  std::optional<std::pair<TimeNs, SE2>> last_estimate_;  // localizing
  std::deque<Pending> pending_;
  TimeNs newest_odometry_ns_ = std::numeric_limits<TimeNs>::min();
  bool finishing_ = false;
  std::vector<localization::LocalizationEstimate> estimates_;
  LiveStats stats_;
  std::uint64_t next_frame_ = 1;

  // The perception thread and what it shares, under mutex_ (taken after
  // state_mutex_ where both are).
  std::unique_ptr<perception::PerceptionFrontEnd> front_end_;
  perception::CameraHealthMonitor health_;  // the thread's alone
  std::mutex mutex_;
  std::condition_variable wake_;
  std::optional<std::pair<std::uint64_t, CameraFrame>> queued_;
  std::uint64_t working_on_ = 0;  // 0: idle
  std::uint64_t done_up_to_ = 0;  // the newest frame perceived or dropped
  std::exception_ptr error_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace parkslam::live

#endif  // PARKSLAM_LIVE_LIVE_SYSTEM_H_
