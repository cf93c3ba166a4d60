#include "parkslam/harness/live_cameras.h"

#include <utility>

#include "parkslam/camera/camera_names.h"
#include "parkslam/harness/rendering_source.h"

namespace parkslam::harness {

LiveCameras::LiveCameras(sim::World world, std::uint64_t render_seed,
                         const perception::PerceptionOptions& perception)
    : LiveCameras(std::move(world), sim::WorldConfig{}, render_seed, perception) {}

LiveCameras::LiveCameras(sim::World world, const sim::WorldConfig& config,
                         std::uint64_t render_seed, const perception::PerceptionOptions& perception)
    : world_(std::move(world)),
      rig_(camera::DefaultRig()),
      renderer_(world_, config, rig_, render_seed),
      front_end_(rig_, perception),
      cameras_(camera::AllCameraNames()) {}

CameraFrame LiveCameras::Render(const SE2& T_map_vehicle, TimeNs t_ns) const {
  return RenderCameraFrame(renderer_, T_map_vehicle, t_ns, cameras_);
}

perception::PerceptionOutput LiveCameras::Perceive(const SE2& T_map_vehicle, TimeNs t_ns) const {
  return front_end_.Process(Render(T_map_vehicle, t_ns));
}

}  // namespace parkslam::harness
