#include "parkslam/harness/frame_renderer.h"

#include <stdexcept>

#include "parkslam/render/renderer.h"
#include "parkslam/scene/lot_renderer.h"

namespace parkslam::harness {

FrameRenderer::FrameRenderer(const sim::World& world, const sim::WorldConfig& config,
                             const camera::CameraRig& rig, std::uint64_t seed, bool whole_images)
    : look_(config.look), whole_images_(whole_images) {
  if (look_ == "grey") {
    grey_ = std::make_unique<render::Renderer>(world, rig, render::RenderOptions{}, seed);
    return;
  }
  scene::LotLook look;
  look.preset = look_;
  look.seed = static_cast<std::uint64_t>(config.look_seed);
  look.parked_share = config.parked_share;
  lot_ = std::make_unique<scene::LotRenderer>(world, rig, look);
}

FrameRenderer::~FrameRenderer() = default;

std::vector<cv::Mat> FrameRenderer::RenderAll(const SE2& T_map_vehicle, TimeNs t_ns,
                                              const std::vector<std::string>& cameras) const {
  if (grey_) return grey_->RenderAll(T_map_vehicle, t_ns, cameras);
  const scene::SceneRendererOptions& o = lot_->renderer().options();
  scene::RenderRequest request;
  request.fisheyes = whole_images_;
  request.top_view = false;
  for (const std::string& name : cameras) request.front = request.front || name == o.front_camera;
  const scene::RenderedScene r = lot_->Render(T_map_vehicle, t_ns, request);
  std::vector<cv::Mat> images;
  for (const std::string& name : cameras) {
    if (name == o.front_camera) {
      images.push_back(r.front);
      continue;
    }
    size_t k = 0;
    while (k < o.fisheye_names.size() && o.fisheye_names[k] != name) ++k;
    if (k == o.fisheye_names.size()) {
      throw std::invalid_argument("the lot renderer has no camera '" + name + "'");
    }
    images.push_back(r.fisheyes[k]);
  }
  return images;
}

}  // namespace parkslam::harness
