#ifndef PARKSLAM_PERCEPTION_FRONT_END_H_
#define PARKSLAM_PERCEPTION_FRONT_END_H_

// The paper's front end on pixels (section III-A and III-B): a camera frame
// set becomes the observations the mapper and the localizer consume. The
// four fisheyes are fused into the top view; slots are detected in it and
// their IDs read; AprilTags are detected in the front camera and located by
// PnP checked by the direct angle.

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "parkslam/camera/camera_model.h"
#include "parkslam/camera/camera_names.h"
#include "parkslam/camera/top_view.h"
#include "parkslam/common/se2.h"
#include "parkslam/map/semantic_map.h"
#include "parkslam/perception/camera_health.h"
#include "parkslam/perception/learned_slot_detector.h"
#include "parkslam/perception/learned_slot_id_reader.h"
#include "parkslam/perception/slot_detector.h"
#include "parkslam/perception/slot_id_reader.h"
#include "parkslam/perception/tag_detector.h"
#include "parkslam/sensor/sensor_log.h"

namespace parkslam::perception {

// Which slot detector and ID reader the front end runs: the classical ones
// (lines and corners, seven-segment digits) or the learned networks
// (docs/learned_perception.md).
enum class DetectorKind { kClassical, kLearned };
// Every kind with its name, for the options file (io/visit_yaml.h).
inline constexpr std::array<std::pair<DetectorKind, const char*>, 2> EnumNames(DetectorKind) {
  return {{{DetectorKind::kClassical, "classical"}, {DetectorKind::kLearned, "learned"}}};
}
const char* ToString(DetectorKind kind);
// "classical" or "learned"; throws std::invalid_argument otherwise.
DetectorKind ParseDetectorKind(const std::string& text);

// The folder of the committed networks (models/ in the source tree).
std::string DefaultModelDir();

// Where the tags of a map are looked for while the car is localized on it
// (active search, as MonoSLAM's): each map tag the predicted pose puts in
// the tag camera's view is searched in a window around its projection,
// grown by the pose's uncertainty; the rest of the image is not searched.
struct TagWindowOptions {
  // Off: the whole band of rows is searched at every frame, also on a map.
  bool enabled = true;
  // The window holds the tag's projection from every pose within this many
  // sigmas of the estimate (the covariance's sigma points).
  double sigmas = 3.0;
  // Pixels around that, for the tag's unknown height and PnP's margin.
  int margin_px = 32;
  // A window whose tag is this many pixels high at the decimation the
  // detector uses is searched at a coarser one (2, 4 or 8), as long as the
  // tag stays at least this high there: a near tag needs no fine search.
  double min_decimated_px = 24.0;
  // Windows that together cost more than this share of the band's search
  // (area over decimation squared): the band is searched whole (a
  // windowed search would save little).
  double max_band_share = 0.5;

  bool IsValid(std::string* error) const;

  template <typename V>
  void VisitFields(V& v) {
    v("enabled", enabled);
    v("sigmas", sigmas);
    v("margin_px", margin_px);
    v("min_decimated_px", min_decimated_px);
    v("max_band_share", max_band_share);
  }
};

// A part of the tag camera's image to look for tags in, at its own
// decimation.
struct TagWindow {
  cv::Rect rect;     // pixels of the tag camera's image
  int decimate = 2;  // libapriltag's quad_decimate there
  int tag_id = -1;   // the map tag it was made for; -1 for a merged one
};

struct PerceptionOptions {
  // The rig's cameras: four fisheyes fused into the top view (in this
  // order: front, rear, left, right) and the front camera for tags.
  std::vector<std::string> fisheye_cameras = camera::FisheyeCameraNames();
  std::string tag_camera = camera::kTagCameraName;
  camera::TopViewOptions top_view;
  // The learned detector is the default since it wins on real views
  // (docs/learned_perception.md, "Where it stands"); the classical one
  // stays for comparison and for top views at other scales.
  DetectorKind detector = DetectorKind::kLearned;
  SlotDetectorOptions slots;
  SlotIdReaderOptions ids;
  // The learned detector and reader; an empty model_path takes the
  // committed network from DefaultModelDir(). The slots' corners are
  // refined on the paint next to them (LearnedSlotDetectorOptions::
  // refine_on_paint), not by the classical detector: as accurate, at a
  // twentieth of its time (docs/learned_perception.md).
  LearnedSlotDetectorOptions learned_slots;
  LearnedSlotIdReaderOptions learned_ids;
  // With the learned detector, the classical reader reads the ID first,
  // and its reading stands where it reads every digit with a confidence of
  // at least classical_id_min_confidence; the network reads the others.
  // The network misses worn seven-segment digits that the classical
  // reader, made for that face, reads; the classical reader reads no other
  // face, and takes a twentieth of the network's time.
  bool learned_ids_with_classical = true;
  double classical_id_min_confidence = 0.5;
  TagDetectorOptions tags;
  bool read_ids = true;
  // Tags hang between these heights above the floor and are looked for
  // from this range on: the front image is searched only in the band of
  // rows where they can appear (a level camera), which halves the
  // detector's time. A band of zero height searches the whole image.
  double tag_min_height_m = 1.0;
  double tag_max_height_m = 1.7;
  double tag_min_range_m = 1.5;
  TagWindowOptions tag_windows;
  // Uncertainty handed to the mapper with each detection: a slot corner
  // (grows with its distance from the top view's centre), a tag's range
  // (grows with range) and bearing.
  double corner_sigma_m = 0.03;
  double corner_sigma_per_m = 0.005;
  double tag_range_sigma_m = 0.03;
  double tag_range_sigma_per_m = 0.01;
  double tag_bearing_sigma_rad = 0.005;
  double tag_yaw_sigma_rad = 0.05;
  double tag_yaw_sigma_per_m = 0.01;

  // The field list, walked by the options file reader (io/options_yaml.h).
  // Not listed: fisheye_cameras. `--detector` on the command line sets
  // detector over the file's.
  template <typename V>
  void VisitFields(V& v) {
    v("tag_camera", tag_camera);
    v("detector", detector);
    v("top_view", top_view);
    v("slots", slots);
    v("ids", ids);
    v("learned_slots", learned_slots);
    v("learned_ids", learned_ids);
    v("learned_ids_with_classical", learned_ids_with_classical);
    v("classical_id_min_confidence", classical_id_min_confidence);
    v("tags", tags);
    v("read_ids", read_ids);
    v("tag_min_height_m", tag_min_height_m);
    v("tag_max_height_m", tag_max_height_m);
    v("tag_min_range_m", tag_min_range_m);
    v("tag_windows", tag_windows);
    v("corner_sigma_m", corner_sigma_m);
    v("corner_sigma_per_m", corner_sigma_per_m);
    v("tag_range_sigma_m", tag_range_sigma_m);
    v("tag_range_sigma_per_m", tag_range_sigma_per_m);
    v("tag_bearing_sigma_rad", tag_bearing_sigma_rad);
    v("tag_yaw_sigma_rad", tag_yaw_sigma_rad);
    v("tag_yaw_sigma_per_m", tag_yaw_sigma_per_m);
  }
};

// Wall time of each stage of one frame, milliseconds.
struct PerceptionTiming {
  double fusion_ms = 0.0, slots_ms = 0.0, ids_ms = 0.0, tags_ms = 0.0;
  double total_ms() const { return fusion_ms + slots_ms + ids_ms + tags_ms; }
};

struct PerceptionOutput {
  SlotObservationFrame slots;
  TagObservationFrame tags;
  // What the stages saw and found, for evaluation and pictures.
  cv::Mat top_view;
  SlotDetection detection;
  std::vector<SlotIdReading> ids;  // one per detected slot
  PerceptionTiming timing;
};

// The name under which a frame brings a top view fused elsewhere.
inline constexpr char kTopViewCamera[] = "top_view";

class PerceptionFrontEnd {
 public:
  // `rig` must hold the fisheye cameras and the tag camera (a pinhole).
  // Throws std::invalid_argument naming what is missing or invalid.
  PerceptionFrontEnd(const camera::CameraRig& rig, const PerceptionOptions& options = {});
  ~PerceptionFrontEnd();

  // Runs every stage on one frame set. Cameras the frame lacks are skipped
  // with their stage (no top view without all four fisheyes). A frame may
  // bring the top view itself instead of the fisheyes, as the image of a
  // camera named kTopViewCamera, in the front end's top-view geometry
  // (options.top_view: size_px square, the vehicle where fusion puts it):
  // a car whose surround-view unit fuses its own. The rig still names the
  // fisheyes (their calibration gives the car's footprint mask). Cameras named
  // in `excluded` (failed: perception/camera_health.h) are left out: a
  // fisheye's part of the top view is black and masked, the tag camera's
  // tags are not looked for. Throws std::invalid_argument when an image's
  // size does not match its camera.
  PerceptionOutput Process(const CameraFrame& frame,
                           const std::vector<std::string>& excluded = {}) const;
  // Its two halves, each into its part of *out (whose frames' times the
  // caller sets): paper III-A, fusion, detection and ID reading into
  // out->slots (and the top view, detection, IDs and their times); paper
  // III-B, the tag camera's tags into out->tags. For a caller that wants
  // the slots' pose before the tags are found (live/live_system.h).
  void PerceiveSlots(const CameraFrame& frame, const std::vector<std::string>& excluded,
                     PerceptionOutput* out) const;
  // With `windows` (as TagWindows gives them), only they are searched, and
  // a tag found in two is kept once (from the window made for it); without,
  // the band of rows where tags can be.
  void PerceiveTags(const CameraFrame& frame, const std::vector<std::string>& excluded,
                    PerceptionOutput* out, const std::vector<TagWindow>* windows = nullptr) const;

  // Where the tag camera sees `tags` from T_map_vehicle, uncertain by
  // `covariance` (x, y, yaw): one window per tag in view within the tag
  // detector's range, aligned to 8 pixels, at the coarsest decimation its
  // size allows; overlapping ones merged where that costs no more. Nothing
  // (search the band) when options.tag_windows is off or the windows
  // would cost more than its max_band_share; an empty list when no tag is
  // in view.
  std::optional<std::vector<TagWindow>> TagWindows(const std::vector<MapTag>& tags,
                                                   const SE2& T_map_vehicle,
                                                   const Eigen::Matrix3d& covariance) const;

  const camera::TopViewFusion& fusion() const { return *fusion_; }
  // 0 on the car's footprint in the top view, 255 elsewhere.
  const cv::Mat& FootprintMask() const { return footprint_mask_; }
  const PerceptionOptions& options() const { return options_; }

 private:
  // The rows of the tag camera where a tag can be (tag_min/max_height_m
  // seen from tag_min_range_m on), for a camera looking level and upright.
  void SetTagBand();
  // The slot detector and ID reader (classical or learned) at the top
  // view's scale, and the tag detector.
  void MakeDetectors();
  // Paper III-A on out->top_view: slots detected (outside `mask`'s zeros),
  // their IDs read, both into out.
  void DetectAndRead(const cv::Mat& mask, PerceptionOutput* out) const;
  // The car's footprint mask, and each fisheye's part of the top view.
  void MakeMasks();
  PerceptionOptions options_;
  camera::CameraConfig tag_camera_;
  int tag_first_row_ = 0, tag_rows_ = 0;  // the searched band of the front image
  camera::CameraIntrinsics tag_band_intrinsics_;
  std::unique_ptr<camera::TopViewFusion> fusion_;
  std::unique_ptr<SlotDetector> slot_detector_;
  std::unique_ptr<SlotIdReader> id_reader_;
  std::unique_ptr<LearnedSlotDetector> learned_detector_;
  std::unique_ptr<LearnedSlotIdReader> learned_reader_;
  std::unique_ptr<TagDetector> tag_detector_;
  cv::Mat footprint_mask_;
  std::vector<cv::Mat> camera_regions_;  // per fisheye, 255 where it counts
};

// A sensor stream on pixels: camera frames of `inner` become slot and tag
// observation frames (at the frame's time) by the front end; the
// observation-level slot and tag frames `inner` may carry are dropped, so
// that everything downstream sees only what the cameras saw. Cameras whose
// images are black or frozen are left out of the frames they fail in.
class PerceptionSource final : public SensorSource {
 public:
  // The windows in which a frame's tags are looked for, asked with the
  // frame's time once its slot frame has been taken (the consumer has
  // seen the slots); nothing searches the band.
  using TagWindowsFn = std::function<std::optional<std::vector<TagWindow>>(TimeNs t_ns)>;

  PerceptionSource(SensorSource& inner, const PerceptionFrontEnd& front_end);
  std::optional<SensorEvent> Next() override;
  // From now on each frame's tags are perceived only when the event after
  // its slot frame is asked for, in the windows `windows` gives.
  void SearchTagsIn(TagWindowsFn windows) { tag_windows_ = std::move(windows); }

  int frames_processed() const { return frames_processed_; }
  // Sum and maximum of the per-frame stage times.
  const PerceptionTiming& total_timing() const { return total_timing_; }
  double max_frame_ms() const { return max_frame_ms_; }
  // The cameras judged black or frozen, and how often (left out then).
  const CameraHealthMonitor& camera_health() const { return health_; }

 private:
  void Count(const PerceptionTiming& timing);

  SensorSource& inner_;
  CameraHealthMonitor health_;
  const PerceptionFrontEnd& front_end_;
  std::optional<SensorEvent> pending_tags_;
  // With tag_windows_: the frame whose tags are still to be perceived.
  struct PendingFrame {
    CameraFrame frame;
    std::vector<std::string> excluded;
    PerceptionOutput out;
  };
  std::optional<PendingFrame> pending_frame_;
  TagWindowsFn tag_windows_;
  int frames_processed_ = 0;
  PerceptionTiming total_timing_;
  double max_frame_ms_ = 0.0;
};

}  // namespace parkslam::perception

#endif  // PARKSLAM_PERCEPTION_FRONT_END_H_
