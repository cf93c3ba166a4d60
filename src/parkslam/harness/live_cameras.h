#ifndef PARKSLAM_HARNESS_LIVE_CAMERAS_H_
#define PARKSLAM_HARNESS_LIVE_CAMERAS_H_

// The simulated car's cameras in a simulated lot: the world, the renderer
// with the default rig, and a perception front end on that rig, built in
// one place for everything that perceives rendered pixels (the sensor
// stream's live mode, trace following, eval-detect, the perception
// benchmark).

#include <cstdint>
#include <string>
#include <vector>

#include "parkslam/common/se2.h"
#include "parkslam/common/time.h"
#include "parkslam/harness/frame_renderer.h"
#include "parkslam/perception/front_end.h"
#include "parkslam/sensor/sensor_log.h"
#include "parkslam/sim/scenario_config.h"
#include "parkslam/sim/world.h"

namespace parkslam::harness {

class LiveCameras {
 public:
  // Renders `world` with the default rig in the look config.look names
  // (FrameRenderer); render_seed draws the grey look's dirt and noise.
  LiveCameras(sim::World world, const sim::WorldConfig& config, std::uint64_t render_seed,
              const perception::PerceptionOptions& perception = {});
  // The grey look.
  LiveCameras(sim::World world, std::uint64_t render_seed,
              const perception::PerceptionOptions& perception = {});

  LiveCameras(const LiveCameras&) = delete;
  LiveCameras& operator=(const LiveCameras&) = delete;

  // The five cameras' images at the pose, as grey planes.
  CameraFrame Render(const SE2& T_map_vehicle, TimeNs t_ns) const;
  // Render, then the front end.
  perception::PerceptionOutput Perceive(const SE2& T_map_vehicle, TimeNs t_ns) const;

  const sim::World& world() const { return world_; }
  const camera::CameraRig& rig() const { return rig_; }
  const FrameRenderer& renderer() const { return renderer_; }
  const perception::PerceptionFrontEnd& front_end() const { return front_end_; }
  const std::vector<std::string>& cameras() const { return cameras_; }

 private:
  sim::World world_;
  camera::CameraRig rig_;
  FrameRenderer renderer_;
  perception::PerceptionFrontEnd front_end_;
  std::vector<std::string> cameras_;
};

}  // namespace parkslam::harness

#endif  // PARKSLAM_HARNESS_LIVE_CAMERAS_H_
