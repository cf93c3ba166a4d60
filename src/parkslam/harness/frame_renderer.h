#ifndef PARKSLAM_HARNESS_FRAME_RENDERER_H_
#define PARKSLAM_HARNESS_FRAME_RENDERER_H_

// The simulated car's camera images of a lot, in the look the scenario's
// world names (sim::WorldConfig::look): "grey", the flat grey floor with
// seven-segment IDs (render/); any other look, the scene renderer's whole
// lot (scene/lot_renderer.h): colour, real fonts, parked cars, lamps.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "parkslam/camera/camera_model.h"
#include "parkslam/common/se2.h"
#include "parkslam/common/time.h"
#include "parkslam/sim/scenario_config.h"
#include "parkslam/sim/world.h"

namespace parkslam::render {
class Renderer;
}
namespace parkslam::scene {
class LotRenderer;
}

namespace parkslam::harness {

class FrameRenderer {
 public:
  // seed draws the grey renderer's dirt and noise; a named look is drawn
  // from config.look_seed, so that the lot looks the same from drive to
  // drive. whole_images: every pixel of the fisheyes (for files); else
  // only those the top view uses (faster; the rest black). Throws
  // std::invalid_argument for an invalid look or a rig without the
  // cameras.
  FrameRenderer(const sim::World& world, const sim::WorldConfig& config,
                const camera::CameraRig& rig, std::uint64_t seed, bool whole_images = false);
  ~FrameRenderer();
  FrameRenderer(const FrameRenderer&) = delete;
  FrameRenderer& operator=(const FrameRenderer&) = delete;

  // The named cameras' images with the car at T_map_vehicle; t_ns seeds
  // the noise. Grey (CV_8UC1) in the grey look, BGR (CV_8UC3) otherwise.
  // Throws std::invalid_argument for a camera it cannot render.
  std::vector<cv::Mat> RenderAll(const SE2& T_map_vehicle, TimeNs t_ns,
                                 const std::vector<std::string>& cameras) const;

  const std::string& look() const { return look_; }

 private:
  std::string look_;
  bool whole_images_ = false;
  std::unique_ptr<render::Renderer> grey_;
  std::unique_ptr<scene::LotRenderer> lot_;
};

}  // namespace parkslam::harness

#endif  // PARKSLAM_HARNESS_FRAME_RENDERER_H_
