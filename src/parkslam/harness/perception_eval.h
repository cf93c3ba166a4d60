#ifndef PARKSLAM_HARNESS_PERCEPTION_EVAL_H_
#define PARKSLAM_HARNESS_PERCEPTION_EVAL_H_

// The simulator's truth in one top view, for scoring the slot detector and
// the ID reader on rendered images with the DMPR-PS rule (eval/
// detection_metrics.h).

#include <vector>

#include "parkslam/camera/top_view.h"
#include "parkslam/common/se2.h"
#include "parkslam/eval/detection_metrics.h"
#include "parkslam/perception/slot_detector.h"
#include "parkslam/sensor/sensor_data.h"
#include "parkslam/sim/world.h"

namespace parkslam::harness {

struct TopViewTruth {
  // Entrance corners (marking points) of the slots in view, one per
  // junction: a corner shared by two slots is one T.
  std::vector<eval::LabelledMarkingPoint> marking_points;
  // Slots whose both entrance corners are in view.
  std::vector<eval::EntranceLine> entrances;
  std::vector<eval::SlotCornersPx> corners;
  std::vector<eval::SlotIdTruth> ids;
  // Junctions a detection on which is neither right nor wrong: back
  // corners (separating line meets back line), and entrance corners in the
  // image but within the margin or by the car. Likewise slots with an
  // entrance corner there.
  std::vector<eval::LabelledMarkingPoint> ignored_points;
  std::vector<eval::EntranceLine> ignored_entrances;
};

// A junction counts as in view when it lies margin_px inside the image
// (far enough for its separating line to show) and min_footprint_gap_px
// outside the masked footprint (mask: 0 on the car); an ID is readable when
// legible and its whole box is in view.
TopViewTruth TruthInTopView(const sim::World& world, const SE2& T_map_vehicle,
                            const camera::TopViewFusion& fusion, const cv::Mat& mask,
                            double margin_px = 48.0, double min_footprint_gap_px = 12.0);

// The detector's output in the metrics' terms.
std::vector<eval::LabelledMarkingPoint> AsLabelled(
    const std::vector<perception::MarkingPoint>& points);
std::vector<eval::EntranceLine> EntrancesOf(const std::vector<perception::DetectedSlot>& slots);
std::vector<eval::SlotCornersPx> CornersOf(const std::vector<perception::DetectedSlot>& slots);

// The indices of detections to score: all but those that match (DMPR-PS
// rule) an ignored item and no true one.
std::vector<int> ScoredPoints(const std::vector<eval::LabelledMarkingPoint>& detected,
                              const std::vector<eval::LabelledMarkingPoint>& truth,
                              const std::vector<eval::LabelledMarkingPoint>& ignored);
std::vector<int> ScoredSlots(const std::vector<eval::EntranceLine>& detected,
                             const std::vector<eval::EntranceLine>& truth,
                             const std::vector<eval::EntranceLine>& ignored);

}  // namespace parkslam::harness

#endif  // PARKSLAM_HARNESS_PERCEPTION_EVAL_H_
