#include "parkslam/scene/labels.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace parkslam::scene {
namespace {

cv::Point2f ToCv(const Eigen::Vector2d& p) {
  return {static_cast<float>(p.x()), static_cast<float>(p.y())};
}

double HiddenShare(const cv::Mat& solids, const Eigen::Vector2d& px) {
  const int cx = static_cast<int>(std::lround(px.x())), cy = static_cast<int>(std::lround(px.y()));
  int hidden = 0, total = 0;
  for (int dy = -2; dy <= 2; ++dy) {
    for (int dx = -2; dx <= 2; ++dx) {
      const int x = cx + dx, y = cy + dy;
      if (x < 0 || y < 0 || x >= solids.cols || y >= solids.rows) continue;
      ++total;
      if (solids.at<std::uint8_t>(y, x) >= 128) ++hidden;
    }
  }
  return total == 0 ? 1.0 : static_cast<double>(hidden) / total;
}

}  // namespace

TopViewLabels LabelTopView(const SceneRenderer& renderer, const Scene& scene,
                           const RenderedScene& rendered, const LabelOptions& options) {
  TopViewLabels labels;
  const camera::TopViewFusion& fusion = renderer.FusionOf(scene);
  const int size = fusion.options().size_px;
  const double px_per_m = size / fusion.options().extent_m;
  std::vector<int> label_of(scene.marks.size(), -1);
  for (size_t i = 0; i < scene.marks.size(); ++i) {
    const MarkingPoint& m = scene.marks[i];
    const auto px = renderer.FusedPixelOf(scene, m.p_vehicle);
    if (!px || px->x() < 0 || px->y() < 0 || px->x() > size - 1 || px->y() > size - 1) continue;
    if (fusion.PrimaryCamera(static_cast<int>(std::lround(px->x())),
                             static_cast<int>(std::lround(px->y()))) < 0) {
      continue;
    }
    if (!rendered.solids.empty() && HiddenShare(rendered.solids, *px) > options.max_hidden_share)
      continue;
    // The direction as it shows: towards the image of a point along the line.
    const auto ahead = renderer.FusedPixelOf(scene, m.p_vehicle + m.direction * (30.0 / px_per_m));
    Eigen::Vector2d d = ahead ? Eigen::Vector2d(*ahead - *px)
                              : Eigen::Vector2d(fusion.VehicleToPixel(m.p_vehicle + m.direction) -
                                                fusion.VehicleToPixel(m.p_vehicle));
    LabelledMark mark;
    mark.px = *px;
    mark.direction_rad = std::atan2(d.y(), d.x());
    mark.is_t = m.is_t;
    mark.scene_mark = static_cast<int>(i);
    label_of[i] = static_cast<int>(labels.marks.size());
    labels.marks.push_back(mark);
  }
  for (size_t s = 0; s < scene.slots.size(); ++s) {
    const Slot& slot = scene.slots[s];
    const int a = label_of[static_cast<size_t>(slot.a)], b = label_of[static_cast<size_t>(slot.b)];
    if (a >= 0 && b >= 0) labels.slots.push_back({a, b, slot.kind, slot.angle_deg});
  }
  // ID crops: the text's box, upright, from the top view.
  for (const FloorText& t : scene.texts) {
    if (t.slot < 0) continue;
    const Slot& slot = scene.slots[static_cast<size_t>(t.slot)];
    const Eigen::Vector2d right = t.right.normalized(), up(-right.y(), right.x());
    const double chars = static_cast<double>(t.text.size());
    const double height_m = 1.6 * t.height_m;
    const double width_m = std::max(height_m * options.id_crop_width_px / options.id_crop_height_px,
                                    1.2 * 0.65 * t.height_m * t.stretch * chars);
    const Eigen::Vector2d tl = t.center - right * (width_m / 2) + up * (height_m / 2);
    const Eigen::Vector2d tr = t.center + right * (width_m / 2) + up * (height_m / 2);
    const Eigen::Vector2d bl = t.center - right * (width_m / 2) - up * (height_m / 2);
    bool inside = true;
    std::vector<cv::Point2f> src;
    for (const Eigen::Vector2d& p :
         {tl, tr, bl, Eigen::Vector2d(t.center + right * (width_m / 2) - up * (height_m / 2))}) {
      const Eigen::Vector2d px = fusion.VehicleToPixel(p);
      inside &= px.x() >= 0 && px.y() >= 0 && px.x() <= size - 1 && px.y() <= size - 1 &&
                fusion.PrimaryCamera(static_cast<int>(std::lround(px.x())),
                                     static_cast<int>(std::lround(px.y()))) >= 0;
      src.push_back(ToCv(px));
    }
    if (!inside) continue;
    const Eigen::Vector2d centre_px = fusion.VehicleToPixel(t.center);
    if (!rendered.solids.empty() && HiddenShare(rendered.solids, centre_px) > 0.0) continue;
    const float w = static_cast<float>(options.id_crop_width_px),
                h = static_cast<float>(options.id_crop_height_px);
    const cv::Point2f dst[3] = {{0, 0}, {w, 0}, {0, h}};
    const cv::Point2f from[3] = {src[0], src[1], src[2]};
    const cv::Mat A = cv::getAffineTransform(from, dst);
    IdCrop crop;
    cv::warpAffine(rendered.top_view, crop.image, A,
                   cv::Size(options.id_crop_width_px, options.id_crop_height_px), cv::INTER_LINEAR,
                   cv::BORDER_REPLICATE);
    crop.text = slot.id_legible ? slot.id : "";
    crop.slot = t.slot;
    labels.ids.push_back(std::move(crop));
  }
  return labels;
}

cv::Mat DrawLabels(const cv::Mat& top_view, const TopViewLabels& labels, const Scene& scene) {
  cv::Mat out = top_view.clone();
  for (const LabelledSlot& s : labels.slots) {
    cv::line(out, ToCv(labels.marks[static_cast<size_t>(s.a)].px),
             ToCv(labels.marks[static_cast<size_t>(s.b)].px), cv::Scalar(0, 220, 0), 2,
             cv::LINE_AA);
  }
  for (const LabelledMark& m : labels.marks) {
    const cv::Scalar colour = m.is_t ? cv::Scalar(0, 0, 255) : cv::Scalar(255, 0, 0);
    cv::circle(out, ToCv(m.px), 6, colour, 2, cv::LINE_AA);
    const Eigen::Vector2d tip =
        m.px + 30.0 * Eigen::Vector2d(std::cos(m.direction_rad), std::sin(m.direction_rad));
    cv::line(out, ToCv(m.px), ToCv(tip), colour, 2, cv::LINE_AA);
  }
  std::vector<int> label_of(scene.marks.size(), -1);
  for (size_t i = 0; i < labels.marks.size(); ++i) {
    label_of[static_cast<size_t>(labels.marks[i].scene_mark)] = static_cast<int>(i);
  }
  for (const IdCrop& id : labels.ids) {
    const Slot& slot = scene.slots[static_cast<size_t>(id.slot)];
    const int a = label_of[static_cast<size_t>(slot.a)], b = label_of[static_cast<size_t>(slot.b)];
    if (a < 0 || b < 0) continue;
    const LabelledMark& ma = labels.marks[static_cast<size_t>(a)];
    const Eigen::Vector2d at =
        (ma.px + labels.marks[static_cast<size_t>(b)].px) / 2 +
        40.0 * Eigen::Vector2d(std::cos(ma.direction_rad), std::sin(ma.direction_rad));
    cv::putText(out, id.text.empty() ? "?" : id.text, ToCv(at), cv::FONT_HERSHEY_SIMPLEX, 0.6,
                cv::Scalar(255, 0, 255), 2, cv::LINE_AA);
  }
  return out;
}

}  // namespace parkslam::scene
