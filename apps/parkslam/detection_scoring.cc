#include "detection_scoring.h"

#include <algorithm>
#include <cstdio>
#include <opencv2/imgproc.hpp>

namespace parkslam::app {

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

namespace {
double Max(const std::vector<double>& v) {
  return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
}

}  // namespace

nlohmann::json ToJson(const Scores& s) {
  nlohmann::json j;
  j["images"] = s.images;
  const auto counts = [](const eval::DetectionCounts& c) {
    return nlohmann::json{{"true_positives", c.true_positives},
                          {"false_positives", c.false_positives},
                          {"false_negatives", c.false_negatives},
                          {"precision", c.precision()},
                          {"recall", c.recall()}};
  };
  j["marking_points"] = counts(s.marking_points);
  j["slots"] = counts(s.slots);
  if (s.corners.entrance_m.count > 0) {
    j["entrance_corner_error_cm"] = {{"mean", 100 * s.corners.entrance_m.mean()},
                                     {"rms", 100 * s.corners.entrance_m.rms()},
                                     {"max", 100 * s.corners.entrance_m.max},
                                     {"count", s.corners.entrance_m.count}};
  }
  if (s.ids.readable > 0) {
    j["ids"] = {{"readable", s.ids.readable},
                {"right", s.ids.correct},
                {"unread", s.ids.unread},
                {"accuracy", s.ids.accuracy()},
                {"unreadable", s.ids.unreadable},
                {"unreadable_read_whole", s.ids.invented},
                {"unreadable_read_whole_right", s.ids.invented_right}};
  }
  if (!s.frame_ms.empty()) {
    j["time_ms_median"] = {{"fusion", Median(s.fusion_ms)},
                           {"slots", Median(s.slots_ms)},
                           {"ids", Median(s.ids_ms)},
                           {"tags", Median(s.tags_ms)},
                           {"frame", Median(s.frame_ms)}};
    j["time_ms_max_frame"] = Max(s.frame_ms);
  } else if (!s.slots_ms.empty()) {
    j["time_ms_median"] = {{"slots", Median(s.slots_ms)}};
  }
  return j;
}

void Print(const Scores& s) {
  std::printf("%d images\n", s.images);
  const auto line = [](const char* what, const eval::DetectionCounts& c) {
    std::printf("%-15s precision %6.2f %%  recall %6.2f %%  (TP %d, FP %d, FN %d)\n", what,
                100 * c.precision(), 100 * c.recall(), c.true_positives, c.false_positives,
                c.false_negatives);
  };
  line("marking points", s.marking_points);
  line("slots", s.slots);
  if (s.corners.entrance_m.count > 0) {
    std::printf("entrance corners: mean %.2f cm, rms %.2f cm, max %.2f cm over %d corners\n",
                100 * s.corners.entrance_m.mean(), 100 * s.corners.entrance_m.rms(),
                100 * s.corners.entrance_m.max, s.corners.entrance_m.count);
  }
  if (s.ids.readable > 0) {
    std::printf("IDs: %d of %d readable IDs right (%.2f %%)\n", s.ids.correct, s.ids.readable,
                100 * s.ids.accuracy());
  }
  if (s.ids.unreadable > 0) {
    std::printf(
        "IDs worn, hidden or absent: %d, read whole anyway %d (%d of them the painted ID)\n",
        s.ids.unreadable, s.ids.invented, s.ids.invented_right);
  }
  if (!s.frame_ms.empty()) {
    std::printf(
        "time per frame (median): fusion %.2f ms, slots %.2f ms, IDs %.2f ms, tags %.2f "
        "ms; total %.2f ms (max %.2f ms)\n",
        Median(s.fusion_ms), Median(s.slots_ms), Median(s.ids_ms), Median(s.tags_ms),
        Median(s.frame_ms), Max(s.frame_ms));
  } else if (!s.slots_ms.empty()) {
    std::printf("slot detection per image (median): %.2f ms\n", Median(s.slots_ms));
  }
}

cv::Mat Overlay(const cv::Mat& image, const std::vector<eval::LabelledMarkingPoint>& truth,
                const perception::SlotDetection& detection,
                const std::vector<eval::EntranceLine>& truth_entrances) {
  cv::Mat out;
  if (image.channels() == 1) {
    cv::cvtColor(image, out, cv::COLOR_GRAY2BGR);
  } else {
    out = image.clone();
  }
  const auto pt = [](const Eigen::Vector2d& p) {
    return cv::Point2f(static_cast<float>(p.x()), static_cast<float>(p.y()));
  };
  for (const eval::LabelledMarkingPoint& t : truth) {
    cv::circle(out, pt(t.px), 10, cv::Scalar(0, 255, 0), 1, cv::LINE_AA);
  }
  // True entrances beside the detected ones: a detected entrance with no
  // green line along it is a false slot.
  const Eigen::Vector2d beside(3.0, 3.0);
  for (const eval::EntranceLine& e : truth_entrances) {
    cv::line(out, pt(e.a_px + beside), pt(e.b_px + beside), cv::Scalar(0, 255, 0), 1, cv::LINE_AA);
  }
  for (const perception::DetectedSlot& s : detection.slots) {
    cv::line(out, pt(s.corners_px[0]), pt(s.corners_px[1]), cv::Scalar(0, 200, 255), 2,
             cv::LINE_AA);
  }
  for (const perception::MarkingPoint& p : detection.marking_points) {
    const Eigen::Vector2d tip =
        p.px + 25.0 * Eigen::Vector2d(std::cos(p.direction_rad), std::sin(p.direction_rad));
    cv::circle(out, pt(p.px), 4, cv::Scalar(0, 0, 255), 2, cv::LINE_AA);
    cv::line(out, pt(p.px), pt(tip), cv::Scalar(0, 0, 255), 2, cv::LINE_AA);
  }
  return out;
}

namespace {

template <typename T>
std::vector<T> Pick(const std::vector<T>& items, const std::vector<int>& indices) {
  std::vector<T> out;
  for (int i : indices) out.push_back(items[static_cast<size_t>(i)]);
  return out;
}

}  // namespace

ImageScore Score(const ImageTruth& truth, const perception::SlotDetection& detection,
                 const std::vector<SlotIdReading>& ids, double pixels_per_m, Scores* scores) {
  const std::vector<eval::LabelledMarkingPoint> all_points =
      harness::AsLabelled(detection.marking_points);
  const std::vector<eval::LabelledMarkingPoint> points =
      Pick(all_points, harness::ScoredPoints(all_points, truth.points, truth.ignored_points));
  const std::vector<eval::EntranceLine> all_entrances = harness::EntrancesOf(detection.slots);
  const std::vector<int> kept =
      harness::ScoredSlots(all_entrances, truth.entrances, truth.ignored_entrances);
  const eval::DetectionMatch mp = eval::MatchMarkingPoints(points, truth.points);
  const eval::DetectionMatch sm = eval::MatchSlots(Pick(all_entrances, kept), truth.entrances);
  scores->marking_points.Add(mp);
  scores->slots.Add(sm);
  ImageScore own;
  own.marking_points.Add(mp);
  own.slots.Add(sm);
  ++scores->images;
  if (truth.corners != nullptr) {
    eval::AddSlotCornerErrors(sm, Pick(harness::CornersOf(detection.slots), kept), *truth.corners,
                              pixels_per_m, &scores->corners);
  }
  if (truth.ids != nullptr) {
    std::vector<std::string> read;
    for (int k : kept) read.push_back(ids[static_cast<size_t>(k)].best());
    eval::AddIdCounts(sm, read, *truth.ids, &scores->ids);
  }
  return own;
}

DriveScorer::DriveScorer(const sim::ScenarioConfig& scenario, std::uint64_t seed,
                         const perception::PerceptionOptions& perception)
    : simulation_(sim::Simulate(scenario, seed)),
      cameras_(simulation_.world, scenario.world, seed, perception),
      truth_(sim::GroundTruthTrajectory(simulation_)) {}

DriveScorer::Frame DriveScorer::ScoreAt(TimeNs t_ns, Scores* scores) const {
  const SE2 pose = *PoseAt(truth_, t_ns);
  const perception::PerceptionFrontEnd& front_end = cameras_.front_end();
  Frame frame;
  frame.out = cameras_.Perceive(pose, t_ns);
  const harness::TopViewTruth tv = harness::TruthInTopView(
      simulation_.world, pose, front_end.fusion(), front_end.FootprintMask());
  const ImageTruth image_truth{tv.marking_points, tv.entrances,      &tv.corners,
                               &tv.ids,           tv.ignored_points, tv.ignored_entrances};
  frame.score = Score(image_truth, frame.out.detection, frame.out.ids,
                      front_end.options().slots.pixels_per_m, scores);
  frame.truth_points = tv.marking_points;
  frame.truth_entrances = tv.entrances;
  return frame;
}

}  // namespace parkslam::app
