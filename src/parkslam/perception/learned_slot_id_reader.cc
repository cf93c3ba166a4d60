#include "parkslam/perception/learned_slot_id_reader.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>

#include "parkslam/common/field_checker.h"

namespace parkslam::perception {
namespace {

constexpr int kCropWidthPx = 96, kCropHeightPx = 32;
// The crop's height over the text's (scene/labels.cc).
constexpr double kBoxOverTextHeight = 1.6;

void CheckImage(const cv::Mat& image) {
  if (image.empty() || image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3)) {
    throw std::invalid_argument("LearnedSlotIdReader: expected an 8-bit grey or BGR image");
  }
}

// The crop as the network takes it; a grey view is converted crop by crop,
// not whole for every slot.
cv::Mat AsBgr(const cv::Mat& image) {
  CheckImage(image);
  if (image.channels() == 3) return image;
  cv::Mat bgr;
  cv::cvtColor(image, bgr, cv::COLOR_GRAY2BGR);
  return bgr;
}

// No camera saw the pixel: 0 in a grey view, pure black in a colour one.
bool Unseen(const cv::Mat& image, int u, int v) {
  return image.channels() == 1 ? image.at<unsigned char>(v, u) == 0
                               : image.at<cv::Vec3b>(v, u) == cv::Vec3b(0, 0, 0);
}

}  // namespace

bool LearnedSlotIdReaderOptions::IsValid(std::string* error) const {
  FieldChecker c(error);
  c.Require(!model_path.empty(), "model_path", "is empty");
  c.Positive(pixels_per_m, "pixels_per_m");
  c.Positive(id_height_m, "id_height_m");
  c.NonNegative(id_setback_m, "id_setback_m");
  c.Rate(min_hypothesis_probability, "min_hypothesis_probability");
  c.InRange(min_digit_probability, min_hypothesis_probability, 1.0, "min_digit_probability", "");
  c.Rate(min_end_probability, "min_end_probability");
  return c.ok();
}

LearnedSlotIdReader::LearnedSlotIdReader(const LearnedSlotIdReaderOptions& options)
    : options_(options) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument("LearnedSlotIdReaderOptions: " + error);
  network_ = std::make_unique<OnnxNetwork>(options.model_path,
                                           std::vector<int>{1, 3, kCropHeightPx, kCropWidthPx},
                                           std::vector<int>{1, kIdPositions, kIdClasses});
}

cv::Mat LearnedSlotIdReader::Crop(const cv::Mat& top_view, const TextBox& box) {
  const Eigen::Vector2d right = box.right_dir.normalized();
  // On screen (y down) a reader's "up" is "right" turned a quarter
  // anticlockwise.
  const Eigen::Vector2d up(right.y(), -right.x());
  const double h = kBoxOverTextHeight * box.text_height_px;
  const double w = h * kCropWidthPx / kCropHeightPx;
  const Eigen::Vector2d tl = box.centre_px - right * (w / 2) + up * (h / 2);
  const Eigen::Vector2d tr = box.centre_px + right * (w / 2) + up * (h / 2);
  const Eigen::Vector2d bl = box.centre_px - right * (w / 2) - up * (h / 2);
  const auto pt = [](const Eigen::Vector2d& p) {
    return cv::Point2f(static_cast<float>(p.x()), static_cast<float>(p.y()));
  };
  const cv::Point2f from[3] = {pt(tl), pt(tr), pt(bl)};
  const cv::Point2f to[3] = {
      {0, 0}, {static_cast<float>(kCropWidthPx), 0}, {0, static_cast<float>(kCropHeightPx)}};
  cv::Mat crop;
  cv::warpAffine(top_view, crop, cv::getAffineTransform(from, to),
                 cv::Size(kCropWidthPx, kCropHeightPx), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  return crop;
}

cv::Mat LearnedSlotIdReader::Probabilities(const cv::Mat& crop) const {
  const cv::Mat out = network_->Forward(cv::dnn::blobFromImage(AsBgr(crop)));
  return out.reshape(1, {kIdPositions, kIdClasses});
}

SlotIdReading LearnedSlotIdReader::Decode(const cv::Mat& p,
                                          const LearnedSlotIdReaderOptions& options) {
  if (p.type() != CV_32F || p.rows != kIdPositions || p.cols != kIdClasses) {
    throw std::invalid_argument("LearnedSlotIdReader::Decode: expected " +
                                std::to_string(kIdPositions) + " x " + std::to_string(kIdClasses) +
                                " floats");
  }
  SlotIdReading reading;
  for (int k = 0; k < kIdPositions; ++k) {
    const float* row = p.ptr<float>(k);
    const int best = static_cast<int>(std::max_element(row, row + kIdClasses) - row);
    // No character, surely: the ID ends here. Unsure whether one stands
    // there, the position is an unread character, so that a worn last
    // digit makes a partial reading ("1?"), not a shorter ID ("1").
    if (best == 0) {
      if (row[0] >= options.min_end_probability) break;
      reading.digits.emplace_back();
      continue;
    }
    DigitReading digit;
    // A character's hypotheses share what the position does not give to
    // "no character".
    const double present = std::max(1e-9, 1.0 - static_cast<double>(row[0]));
    for (int c = 1; c < kIdClasses; ++c) {
      const double probability = row[c] / present;
      if (probability >= options.min_hypothesis_probability) {
        digit.hypotheses.push_back({kIdAlphabet[c - 1], probability});
      }
    }
    std::sort(digit.hypotheses.begin(), digit.hypotheses.end(),
              [](const DigitHypothesis& a, const DigitHypothesis& b) {
                return a.probability > b.probability;
              });
    if (digit.hypotheses.empty() ||
        digit.hypotheses.front().probability < options.min_digit_probability) {
      digit.hypotheses.clear();
    }
    reading.digits.push_back(digit);
  }
  if (std::none_of(reading.digits.begin(), reading.digits.end(),
                   [](const DigitReading& d) { return d.read(); })) {
    return {};
  }
  return reading;
}

SlotIdReading LearnedSlotIdReader::ReadBox(const cv::Mat& top_view, const TextBox& box) const {
  CheckImage(top_view);
  // The text's own box (without the crop's margins) must lie in view, on
  // pixels some camera saw.
  const Eigen::Vector2d right = box.right_dir.normalized(), up(right.y(), -right.x());
  const double h = box.text_height_px, w = kBoxOverTextHeight * h * kCropWidthPx / kCropHeightPx;
  for (const double a : {-0.5, 0.0, 0.5}) {
    for (const double b : {-0.5, 0.5}) {
      const Eigen::Vector2d p = box.centre_px + a * w * right + b * h * up;
      const int u = static_cast<int>(std::lround(p.x())), v = static_cast<int>(std::lround(p.y()));
      if (u < 0 || v < 0 || u >= top_view.cols || v >= top_view.rows) return {};
      if (Unseen(top_view, u, v)) return {};
    }
  }
  return Decode(Probabilities(Crop(top_view, box)), options_);
}

SlotIdReading LearnedSlotIdReader::Read(const cv::Mat& top_view,
                                        const EntranceInImage& entrance) const {
  const Eigen::Vector2d entrance_px = entrance.corner1_px - entrance.corner0_px;
  if (entrance_px.norm() < 1.0) return {};
  const double s = options_.pixels_per_m;
  // Upright for a reader in the aisle: the text's top lies into the slot.
  const Eigen::Vector2d up = entrance.depth_dir_px.normalized();
  TextBox box;
  box.right_dir = Eigen::Vector2d(-up.y(), up.x());
  box.centre_px = (entrance.corner0_px + entrance.corner1_px) / 2 +
                  up * s * (options_.id_setback_m + options_.id_height_m / 2);
  box.text_height_px = s * options_.id_height_m;
  return ReadBox(top_view, box);
}

}  // namespace parkslam::perception
