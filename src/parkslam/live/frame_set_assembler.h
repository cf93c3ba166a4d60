#ifndef PARKSLAM_LIVE_FRAME_SET_ASSEMBLER_H_
#define PARKSLAM_LIVE_FRAME_SET_ASSEMBLER_H_

// Frame sets from the images of a car's cameras as they arrive one by one
// (a driver per camera, one message each): the live counterpart of
// import-rosbag's frame sets (docs/your_car.md, "ROS bags"). Each image of
// the reference camera (the first one named) is set with one image of
// every other camera at most max_skew apart, the nearest one received by
// the time the set is complete. A set is given out as soon as every camera
// has an image for it, so a rig that triggers its cameras together gives
// each set at its last image, with no wait for later ones.
//
// A reference image that can no longer be completed (some camera's images
// have gone past it beyond the skew with none near it) is dropped, as is an
// image older than its camera's last one (out of order) or than the last
// set given, and each camera keeps at most `buffer` images waiting.

#include <cstddef>
#include <deque>
#include <map>
#include <string>
#include <vector>

#include "parkslam/common/time.h"
#include "parkslam/sensor/sensor_data.h"

namespace parkslam::live {

struct FrameSetStats {
  int sets = 0;
  // Images that went into no set: the reference camera's that found no
  // partner, the others' that no reference image took, and those that came
  // out of order.
  int images_unmatched = 0;
  int images_out_of_order = 0;
};

class FrameSetAssembler {
 public:
  // cameras: the rig's cameras whose images make a set, the reference
  // first ("front"); the sets name them in this order. Throws
  // std::invalid_argument for no camera, a name given twice, a negative
  // skew or a zero buffer.
  FrameSetAssembler(std::vector<std::string> cameras, TimeNs max_skew_ns, std::size_t buffer = 8);

  // One camera's image; returns the sets it completed (oldest first).
  // Throws std::invalid_argument for a camera not in the set.
  std::vector<CameraFrame> Add(const std::string& camera, TimeNs t_ns, ImagePlane image);

  const FrameSetStats& stats() const { return stats_; }
  const std::vector<std::string>& cameras() const { return cameras_; }

 private:
  struct Image {
    TimeNs t_ns = 0;
    ImagePlane plane;
  };
  // Gives out the sets complete now, and drops reference images that can
  // no longer be completed.
  void Collect(std::vector<CameraFrame>* out);

  std::vector<std::string> cameras_;
  TimeNs max_skew_ns_;
  std::size_t buffer_;
  std::vector<std::deque<Image>> waiting_;  // per camera, oldest first
  std::vector<TimeNs> last_ns_;             // per camera, the newest image's time
  TimeNs last_set_ns_;
  FrameSetStats stats_;
};

}  // namespace parkslam::live

#endif  // PARKSLAM_LIVE_FRAME_SET_ASSEMBLER_H_
