#ifndef PARKSLAM_APPS_DETECTION_SCORING_H_
#define PARKSLAM_APPS_DETECTION_SCORING_H_

// Scoring the front end's slots, marking points and IDs against a truth
// with the DMPR-PS rule, shared by `eval-detect` and the perception part of
// `demo` (and its report).

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "parkslam/common/trajectory.h"
#include "parkslam/eval/detection_metrics.h"
#include "parkslam/harness/live_cameras.h"
#include "parkslam/harness/perception_eval.h"
#include "parkslam/perception/front_end.h"
#include "parkslam/perception/slot_detector.h"
#include "parkslam/sim/simulator.h"

namespace parkslam::app {

struct Scores {
  eval::DetectionCounts marking_points, slots;
  eval::SlotCornerErrors corners;
  eval::IdCounts ids;
  int images = 0;
  std::vector<double> frame_ms, fusion_ms, slots_ms, ids_ms, tags_ms;
};

double Median(std::vector<double> v);
nlohmann::json ToJson(const Scores& s);
void Print(const Scores& s);

// The image with the truth's marking points (green circles) and entrance
// lines (thin green, drawn 3 px aside), and the detections (red points
// with their direction, orange entrance lines).
cv::Mat Overlay(const cv::Mat& image, const std::vector<eval::LabelledMarkingPoint>& truth,
                const perception::SlotDetection& detection,
                const std::vector<eval::EntranceLine>& truth_entrances = {});

// What one image is scored against; the pointers are null where the truth
// does not say (the ps2.0 labels have no corners beyond the entrance, no
// IDs).
struct ImageTruth {
  std::vector<eval::LabelledMarkingPoint> points;
  std::vector<eval::EntranceLine> entrances;
  const std::vector<eval::SlotCornersPx>* corners = nullptr;
  const std::vector<eval::SlotIdTruth>* ids = nullptr;
  std::vector<eval::LabelledMarkingPoint> ignored_points;
  std::vector<eval::EntranceLine> ignored_entrances;
};

// One image's own counts, for picking pictures.
struct ImageScore {
  eval::DetectionCounts marking_points, slots;
  // False and missed marking points and slots.
  int errors() const {
    return marking_points.false_positives + marking_points.false_negatives + slots.false_positives +
           slots.false_negatives;
  }
  bool any_error() const { return errors() > 0; }
};

// Scores one image into `scores`; returns its own counts.
ImageScore Score(const ImageTruth& truth, const perception::SlotDetection& detection,
                 const std::vector<SlotIdReading>& ids, double pixels_per_m, Scores* scores);

// A simulated drive whose cameras are rendered at the true pose, fused and
// run through the front end, frame by frame, and scored against the
// simulator's truth in the top view (eval-detect, demo).
class DriveScorer {
 public:
  DriveScorer(const sim::ScenarioConfig& scenario, std::uint64_t seed,
              const perception::PerceptionOptions& perception);
  DriveScorer(const DriveScorer&) = delete;
  DriveScorer& operator=(const DriveScorer&) = delete;

  struct Frame {
    perception::PerceptionOutput out;
    std::vector<eval::LabelledMarkingPoint> truth_points;  // for Overlay()
    std::vector<eval::EntranceLine> truth_entrances;
    ImageScore score;
  };
  // The frame at t_ns, its counts added to *scores.
  Frame ScoreAt(TimeNs t_ns, Scores* scores) const;

  const Trajectory& truth() const { return truth_; }

 private:
  sim::Simulation simulation_;
  harness::LiveCameras cameras_;
  Trajectory truth_;
};

}  // namespace parkslam::app

#endif  // PARKSLAM_APPS_DETECTION_SCORING_H_
