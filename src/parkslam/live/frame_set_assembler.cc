#include "parkslam/live/frame_set_assembler.h"

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <utility>

namespace parkslam::live {

FrameSetAssembler::FrameSetAssembler(std::vector<std::string> cameras, TimeNs max_skew_ns,
                                     std::size_t buffer)
    : cameras_(std::move(cameras)),
      max_skew_ns_(max_skew_ns),
      buffer_(buffer),
      waiting_(cameras_.size()),
      last_ns_(cameras_.size(), std::numeric_limits<TimeNs>::min()),
      last_set_ns_(std::numeric_limits<TimeNs>::min()) {
  if (cameras_.empty()) throw std::invalid_argument("frame sets: no camera");
  for (std::size_t k = 0; k < cameras_.size(); ++k) {
    if (std::find(cameras_.begin(), cameras_.begin() + k, cameras_[k]) != cameras_.begin() + k) {
      throw std::invalid_argument("frame sets: camera '" + cameras_[k] + "' named twice");
    }
  }
  if (max_skew_ns_ < 0) throw std::invalid_argument("frame sets: the skew must not be negative");
  if (buffer_ == 0) throw std::invalid_argument("frame sets: the buffer must hold an image");
}

std::vector<CameraFrame> FrameSetAssembler::Add(const std::string& camera, TimeNs t_ns,
                                                ImagePlane image) {
  const auto it = std::find(cameras_.begin(), cameras_.end(), camera);
  if (it == cameras_.end()) {
    throw std::invalid_argument("frame sets: camera '" + camera + "' is not in the set");
  }
  const std::size_t k = static_cast<std::size_t>(it - cameras_.begin());
  std::vector<CameraFrame> out;
  if (t_ns <= last_ns_[k] || (k == 0 && t_ns <= last_set_ns_)) {
    ++stats_.images_out_of_order;
    return out;
  }
  last_ns_[k] = t_ns;
  waiting_[k].push_back({t_ns, std::move(image)});
  if (waiting_[k].size() > buffer_) {
    waiting_[k].pop_front();
    ++stats_.images_unmatched;
  }
  Collect(&out);
  return out;
}

void FrameSetAssembler::Collect(std::vector<CameraFrame>* out) {
  const std::size_t n = cameras_.size();
  while (!waiting_[0].empty()) {
    const Image& reference = waiting_[0].front();
    std::vector<std::size_t> chosen(n, 0);
    bool complete = true, hopeless = false;
    for (std::size_t k = 1; k < n; ++k) {
      const std::deque<Image>& list = waiting_[k];
      std::size_t best = list.size();
      TimeNs best_dt = max_skew_ns_ + 1;
      for (std::size_t i = 0; i < list.size(); ++i) {
        const TimeNs dt = std::llabs(list[i].t_ns - reference.t_ns);
        if (dt < best_dt) best = i, best_dt = dt;
      }
      if (best < list.size()) {
        chosen[k] = best;
        continue;
      }
      complete = false;
      // This camera's next images come after its last one, which is
      // already past the reference by more than the skew.
      if (last_ns_[k] > reference.t_ns + max_skew_ns_) hopeless = true;
    }
    if (complete) {
      CameraFrame frame;
      frame.t_ns = reference.t_ns;
      frame.cameras = cameras_;
      frame.images.push_back(reference.plane);
      for (std::size_t k = 1; k < n; ++k) {
        frame.images.push_back(waiting_[k][chosen[k]].plane);
        // The images before the one taken are farther from every later
        // reference image than it is.
        stats_.images_unmatched += static_cast<int>(chosen[k]);
        waiting_[k].erase(waiting_[k].begin(),
                          waiting_[k].begin() + static_cast<std::ptrdiff_t>(chosen[k]) + 1);
      }
      last_set_ns_ = frame.t_ns;
      waiting_[0].pop_front();
      ++stats_.sets;
      out->push_back(std::move(frame));
      continue;
    }
    if (!hopeless) break;
    waiting_[0].pop_front();
    ++stats_.images_unmatched;
  }
  // The others' images that no reference image, waiting or to come, can
  // take: the next reference image comes after the camera's last one.
  if (last_ns_[0] == std::numeric_limits<TimeNs>::min()) return;  // none yet
  const TimeNs oldest_reference_ns =
      waiting_[0].empty() ? last_ns_[0] + 1 : waiting_[0].front().t_ns;
  for (std::size_t k = 1; k < n; ++k) {
    while (!waiting_[k].empty() && waiting_[k].front().t_ns < oldest_reference_ns - max_skew_ns_) {
      waiting_[k].pop_front();
      ++stats_.images_unmatched;
    }
  }
}

}  // namespace parkslam::live
