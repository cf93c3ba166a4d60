#ifndef PARKSLAM_HARNESS_RENDERING_SOURCE_H_
#define PARKSLAM_HARNESS_RENDERING_SOURCE_H_

// The simulator's cameras, live: passes a sensor stream through and adds,
// every 1 / rate_hz, the frame set the rig's cameras see at the true pose,
// rendered on the fly and never written to disk.

#include <optional>
#include <string>
#include <vector>

#include "parkslam/common/trajectory.h"
#include "parkslam/harness/frame_renderer.h"
#include "parkslam/sensor/sensor_log.h"

namespace parkslam::harness {

// Renders a frame set into a CameraFrame (grey planes: colour looks are
// taken to grey, as the dataset reader reads images).
CameraFrame RenderCameraFrame(const FrameRenderer& renderer, const SE2& T_map_vehicle, TimeNs t_ns,
                              const std::vector<std::string>& cameras);

class RenderingSource final : public SensorSource {
 public:
  // `truth` gives the true pose at each frame time; frames are rendered
  // from its start to its end. inner, renderer and truth must outlive the
  // source.
  RenderingSource(SensorSource& inner, const FrameRenderer& renderer, const Trajectory& truth,
                  std::vector<std::string> cameras, double rate_hz);
  std::optional<SensorEvent> Next() override;
  int frames_rendered() const { return frames_rendered_; }

 private:
  SensorSource& inner_;
  const FrameRenderer& renderer_;
  const Trajectory& truth_;
  std::vector<std::string> cameras_;
  TimeNs period_ns_;
  TimeNs next_frame_ns_;
  std::optional<SensorEvent> pending_;
  bool inner_done_ = false;
  int frames_rendered_ = 0;
};

}  // namespace parkslam::harness

#endif  // PARKSLAM_HARNESS_RENDERING_SOURCE_H_
