#include "parkslam/harness/rendering_source.h"

#include <stdexcept>

#include "parkslam/camera/image_plane.h"

#include <opencv2/imgproc.hpp>

namespace parkslam::harness {

CameraFrame RenderCameraFrame(const FrameRenderer& renderer, const SE2& T_map_vehicle, TimeNs t_ns,
                              const std::vector<std::string>& cameras) {
  CameraFrame frame;
  frame.t_ns = t_ns;
  frame.cameras = cameras;
  for (const cv::Mat& image : renderer.RenderAll(T_map_vehicle, t_ns, cameras)) {
    if (image.channels() == 3) {
      cv::Mat grey;
      cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
      frame.images.push_back(camera::ToImagePlane(grey));
    } else {
      frame.images.push_back(camera::ToImagePlane(image));
    }
  }
  return frame;
}

RenderingSource::RenderingSource(SensorSource& inner, const FrameRenderer& renderer,
                                 const Trajectory& truth, std::vector<std::string> cameras,
                                 double rate_hz)
    : inner_(inner), renderer_(renderer), truth_(truth), cameras_(std::move(cameras)) {
  if (!(rate_hz > 0.0)) throw std::invalid_argument("image rate must be positive");
  if (truth_.size() < 2) throw std::invalid_argument("rendering needs the true trajectory");
  period_ns_ = FromSeconds(1.0 / rate_hz);
  next_frame_ns_ = truth_.front().t_ns;
}

std::optional<SensorEvent> RenderingSource::Next() {
  if (!pending_ && !inner_done_) {
    pending_ = inner_.Next();
    inner_done_ = !pending_.has_value();
  }
  const bool frame_due =
      next_frame_ns_ <= truth_.back().t_ns && (!pending_ || next_frame_ns_ < EventTime(*pending_));
  if (frame_due) {
    const TimeNs t = next_frame_ns_;
    next_frame_ns_ += period_ns_;
    ++frames_rendered_;
    return RenderCameraFrame(renderer_, *PoseAt(truth_, t), t, cameras_);
  }
  std::optional<SensorEvent> event = std::move(pending_);
  pending_.reset();
  return event;
}

}  // namespace parkslam::harness
