#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "commands.h"
#include "image_files.h"
#include "parkslam/io/output_guard.h"
#include "parkslam/perception/front_end.h"
#include "parkslam/perception/learned_slot_detector.h"
#include "parkslam/perception/learned_slot_id_reader.h"
#include "parkslam/perception/slot_detector.h"
#include "parkslam/perception/slot_id_reader.h"

namespace parkslam::app {
namespace detect_command {

cv::Point2f ToCv(const Eigen::Vector2d& p) {
  return {static_cast<float>(p.x()), static_cast<float>(p.y())};
}

// The detections drawn over the image: painted lines found (thin purple),
// marking points as circles with their direction, entrance lines solid,
// guessed sides thin, IDs as text.
cv::Mat DrawOverlay(const cv::Mat& image, const perception::SlotDetection& detection,
                    const std::vector<SlotIdReading>& ids) {
  cv::Mat overlay;
  if (image.channels() == 1) {
    cv::cvtColor(image, overlay, cv::COLOR_GRAY2BGR);
  } else {
    overlay = image.clone();
  }
  const cv::Scalar entrance_colour(0, 200, 0), guessed_colour(0, 140, 255);
  for (const perception::PaintedLine& line : detection.lines) {
    cv::line(overlay, ToCv(line.a_px), ToCv(line.b_px), cv::Scalar(200, 0, 200), 1, cv::LINE_AA);
  }
  for (size_t k = 0; k < detection.slots.size(); ++k) {
    const perception::DetectedSlot& slot = detection.slots[k];
    const auto& c = slot.corners_px;
    cv::line(overlay, ToCv(c[0]), ToCv(c[1]), entrance_colour, 2, cv::LINE_AA);
    cv::line(overlay, ToCv(c[1]), ToCv(c[2]), guessed_colour, 1, cv::LINE_AA);
    cv::line(overlay, ToCv(c[2]), ToCv(c[3]), guessed_colour, 1, cv::LINE_AA);
    cv::line(overlay, ToCv(c[3]), ToCv(c[0]), guessed_colour, 1, cv::LINE_AA);
    const std::string id = ids[k].best();
    if (!id.empty()) {
      const Eigen::Vector2d at = (c[0] + c[1]) / 2 + slot.depth_dir_px * 60.0;
      cv::putText(overlay, id, ToCv(at), cv::FONT_HERSHEY_SIMPLEX, 0.7, cv::Scalar(255, 0, 255), 2,
                  cv::LINE_AA);
    }
  }
  for (const perception::MarkingPoint& p : detection.marking_points) {
    const cv::Scalar colour =
        p.shape == perception::MarkingShape::kT ? cv::Scalar(0, 0, 255) : cv::Scalar(255, 0, 0);
    cv::circle(overlay, ToCv(p.px), 6, colour, 2, cv::LINE_AA);
    const Eigen::Vector2d tip =
        p.px + 30.0 * Eigen::Vector2d(std::cos(p.direction_rad), std::sin(p.direction_rad));
    cv::line(overlay, ToCv(p.px), ToCv(tip), colour, 2, cv::LINE_AA);
  }
  return overlay;
}

struct Options {
  std::string image, out;
  std::string detector = "learned";
  std::string models;
  double pixels_per_m = 60.0;
  bool json = false, no_ids = false;
};

// The top view's grey levels; fails on an image too small or of another kind.
cv::Mat GreyTopView(const cv::Mat& image, const std::string& path) {
  if (image.cols < 64 || image.rows < 64) {
    throw std::runtime_error(path + ": an image of " + std::to_string(image.cols) + " x " +
                             std::to_string(image.rows) +
                             " pixels; a top view needs at least 64 x 64");
  }
  if (image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3)) {
    throw std::runtime_error(path + ": expected an 8-bit grey or colour image");
  }
  cv::Mat grey;
  if (image.channels() == 3) {
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  } else {
    grey = image;
  }
  return grey;
}

// The painted ID of every detected slot. With `learned` (the ID network's
// file), as the front end reads them: the classical reader first, the
// network where it does not read every digit surely.
std::vector<SlotIdReading> ReadIds(const cv::Mat& image, const cv::Mat& grey,
                                   const perception::SlotDetection& detection, double pixels_per_m,
                                   const std::string& learned) {
  std::vector<SlotIdReading> ids(detection.slots.size());
  perception::SlotIdReaderOptions reader_options;
  reader_options.pixels_per_m = pixels_per_m;
  const perception::SlotIdReader reader(reader_options);
  std::unique_ptr<perception::LearnedSlotIdReader> network;
  if (!learned.empty()) {
    perception::LearnedSlotIdReaderOptions network_options;
    network_options.model_path = learned;
    network = std::make_unique<perception::LearnedSlotIdReader>(network_options);
  }
  const double min_confidence = perception::PerceptionOptions{}.classical_id_min_confidence;
  for (size_t k = 0; k < detection.slots.size(); ++k) {
    const perception::DetectedSlot& slot = detection.slots[k];
    const perception::EntranceInImage entrance{slot.corners_px[0], slot.corners_px[1],
                                               slot.depth_dir_px};
    ids[k] = reader.Read(grey, entrance);
    const bool sure = !ids[k].empty() && !ids[k].partial() && ids[k].confidence() >= min_confidence;
    if (network != nullptr && !sure) ids[k] = network->Read(image, entrance);
  }
  return ids;
}

nlohmann::json DetectionJson(const perception::SlotDetection& detection,
                             const std::vector<SlotIdReading>& ids) {
  nlohmann::json j = {{"marking_points", nlohmann::json::array()},
                      {"slots", nlohmann::json::array()}};
  for (const perception::MarkingPoint& p : detection.marking_points) {
    j["marking_points"].push_back({{"x", p.px.x()},
                                   {"y", p.px.y()},
                                   {"direction_rad", p.direction_rad},
                                   {"shape", perception::ToString(p.shape)},
                                   {"score", p.score}});
  }
  for (size_t k = 0; k < detection.slots.size(); ++k) {
    const perception::DetectedSlot& slot = detection.slots[k];
    nlohmann::json corners = nlohmann::json::array();
    for (const Eigen::Vector2d& c : slot.corners_px) corners.push_back({c.x(), c.y()});
    const std::string id = ids[k].best();
    // A partial reading ("3?") is not an ID; it is reported as such.
    const bool full = !id.empty() && !ids[k].partial();
    nlohmann::json entry = {{"entrance_px",
                             {{slot.corners_px[0].x(), slot.corners_px[0].y()},
                              {slot.corners_px[1].x(), slot.corners_px[1].y()}}},
                            {"corners_px", corners},
                            {"corner_observed", slot.corner_observed},
                            {"confidence", slot.confidence},
                            {"id", full ? nlohmann::json(id) : nlohmann::json(nullptr)},
                            {"id_confidence", full ? ids[k].confidence() : 0.0}};
    if (ids[k].partial()) entry["partial_id"] = id;
    j["slots"].push_back(entry);
  }
  return j;
}

void PrintDetection(const perception::SlotDetection& detection,
                    const std::vector<SlotIdReading>& ids) {
  std::printf("%zu marking points, %zu slots\n", detection.marking_points.size(),
              detection.slots.size());
  for (const perception::MarkingPoint& p : detection.marking_points) {
    std::printf("marking point %s at (%.1f, %.1f) px, direction %.1f deg\n",
                perception::ToString(p.shape), p.px.x(), p.px.y(), p.direction_rad * 180.0 / M_PI);
  }
  for (size_t k = 0; k < detection.slots.size(); ++k) {
    const perception::DetectedSlot& slot = detection.slots[k];
    const std::string id = ids[k].best();
    std::printf("slot: entrance (%.1f, %.1f)-(%.1f, %.1f) px, id %s (%.2f)\n",
                slot.corners_px[0].x(), slot.corners_px[0].y(), slot.corners_px[1].x(),
                slot.corners_px[1].y(), id.empty() ? "-" : id.c_str(), ids[k].confidence());
  }
}

void Run(const Options& o) {
  io::CheckOutputsSpareInputs({{o.out, "--out"}}, {{o.image, "--image"}, {o.models, "--models"}});
  const cv::Mat image = ReadImage(o.image, cv::IMREAD_UNCHANGED);
  const cv::Mat grey = GreyTopView(image, o.image);
  const bool learned = o.detector == "learned";
  if (learned && o.pixels_per_m != perception::kLearnedPixelsPerM) {
    char got[32];
    std::snprintf(got, sizeof got, "%g", o.pixels_per_m);
    throw std::invalid_argument(
        std::string("--pixels-per-m: --detector learned needs 60 (its networks learned 600 px "
                    "for 10 m), got ") +
        got + "; --detector classical takes any scale");
  }
  const std::string models = o.models.empty() ? perception::DefaultModelDir() : o.models;
  perception::SlotDetection detection;
  if (learned) {
    perception::LearnedSlotDetectorOptions detector_options;
    detector_options.model_path = models + "/marking_points.onnx";
    cv::Mat colour = image;
    if (image.channels() == 1) cv::cvtColor(image, colour, cv::COLOR_GRAY2BGR);
    detection = perception::LearnedSlotDetector(detector_options).Detect(colour);
  } else {
    perception::SlotDetectorOptions detector_options;
    detector_options.pixels_per_m = o.pixels_per_m;
    detection = perception::SlotDetector(detector_options).Detect(grey);
  }
  const std::vector<SlotIdReading> ids =
      o.no_ids ? std::vector<SlotIdReading>(detection.slots.size())
               : ReadIds(image.channels() == 1 ? grey : image, grey, detection, o.pixels_per_m,
                         learned ? models + "/slot_ids.onnx" : "");

  if (!o.out.empty()) WriteImage(o.out, DrawOverlay(image, detection, ids));

  const nlohmann::json j = DetectionJson(detection, ids);
  if (o.json) {
    std::cout << j.dump() << "\n";
    return;
  }
  PrintDetection(detection, ids);
  if (!o.out.empty()) std::printf("wrote %s\n", o.out.c_str());
}

}  // namespace detect_command

void AddDetectCommand(CLI::App& app) {
  using namespace detect_command;
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "detect",
      "Detect marking points and parking slots in one top-view image and read the slots' "
      "painted IDs (the paper's III-A)");
  cmd->add_option("--image", options->image, "Top-view image (grey or colour), the car pointing up")
      ->required();
  cmd->add_option("--out", options->out, "Also write the image with the detections drawn over it");
  cmd->add_option("--pixels-per-m", options->pixels_per_m,
                  "Top-view scale (ps2.0 and the default top view: 600 px for 10 m)")
      ->check(CLI::Range(10.0, 500.0))
      ->capture_default_str();
  AddDetectorOption(cmd, &options->detector);
  cmd->add_option("--models", options->models,
                  "Folder holding marking_points.onnx and slot_ids.onnx for --detector learned "
                  "(default: the committed networks; 60 px/m only)");
  cmd->add_flag("--no-ids", options->no_ids, "Do not read slot IDs");
  cmd->add_flag("--json", options->json,
                "Print one JSON object: marking_points (x, y, direction_rad, shape) and slots "
                "(entrance_px, corners_px, id, id_confidence), 0-based pixels");
  cmd->callback([options] { Run(*options); });
}

}  // namespace parkslam::app
