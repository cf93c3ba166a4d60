#ifndef PARKSLAM_SCENE_LABELS_H_
#define PARKSLAM_SCENE_LABELS_H_

// The labels of a rendered scene's top view, as ps2.0 / DMPR-PS label
// them: the marking points in view with their direction and shape, the
// slots whose two marking points are both in view, and crops of the slot
// IDs with their text for an ID reader.

#include <Eigen/Core>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "parkslam/scene/scene.h"
#include "parkslam/scene/scene_renderer.h"

namespace parkslam::scene {

struct LabelledMark {
  Eigen::Vector2d px = Eigen::Vector2d::Zero();  // 0-based top-view pixel
  double direction_rad = 0.0;                    // image angle of the separating line, y down
  bool is_t = true;
  int scene_mark = -1;
};

struct LabelledSlot {
  int a = 0, b = 0;  // indices into TopViewLabels::marks
  SlotKind kind = SlotKind::kPerpendicular;
  double angle_deg = 90.0;
};

struct IdCrop {
  std::string text;  // the painted ID; empty when it cannot be read
  cv::Mat image;     // CV_8UC3, upright for the reader
  int slot = -1;     // index into Scene::slots
};

struct TopViewLabels {
  std::vector<LabelledMark> marks;
  std::vector<LabelledSlot> slots;
  std::vector<IdCrop> ids;
};

struct LabelOptions {
  // A marking point is labelled when it shows in the image, off the car's
  // footprint, and a solid hides no more than this share of the 5 x 5
  // pixels around it.
  double max_hidden_share = 0.5;
  int id_crop_width_px = 96;
  int id_crop_height_px = 32;
};

// `rendered` must hold the solids mask (RenderRequest::solids).
TopViewLabels LabelTopView(const SceneRenderer& renderer, const Scene& scene,
                           const RenderedScene& rendered, const LabelOptions& options = {});

// The labels drawn over a copy of the top view: T points red, L blue, each
// with its direction, entrance lines green, IDs' text magenta.
cv::Mat DrawLabels(const cv::Mat& top_view, const TopViewLabels& labels, const Scene& scene);

}  // namespace parkslam::scene

#endif  // PARKSLAM_SCENE_LABELS_H_
