#include "parkslam/perception/digit_classifier.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>

#include "parkslam/font/digit_font.h"

namespace parkslam::perception {
namespace {

int ArgMax(const ClassProbabilities& p) {
  return static_cast<int>(std::max_element(p.begin(), p.end()) - p.begin());
}

// The seven-segment font, shared with the simulator's ground raster.
TEST(DigitFontTest, SegmentsOfTheDigits) {
  EXPECT_EQ(font::DigitSegments('8'), 0b1111111);
  EXPECT_EQ(font::DigitSegments('1'), 0b0000110);  // b and c
  EXPECT_EQ(font::DigitSegments('7'), 0b0000111);
  EXPECT_EQ(font::DigitSegments('?'), 0);
  EXPECT_DOUBLE_EQ(font::IdWidth(2, 0.6), 0.6 * (2 * 0.55 + 0.25));
  EXPECT_DOUBLE_EQ(font::IdWidth(3, 0.6), 0.6 * (3 * 0.55 + 2 * 0.25));
  EXPECT_DOUBLE_EQ(font::IdWidth(0, 0.6), 0.0);
}

TEST(DigitFontTest, DrawsTheLitSegmentsOnly) {
  // A digit 100 px tall, its foot-left corner at pixel (20, 119), upright.
  cv::Mat image = cv::Mat::zeros(130, 100, CV_8U);
  font::DrawSevenSegmentDigit('1', 100.0, 15.0, {20.0, 119.0}, {1.0, 0.0}, {0.0, -1.0}, 255,
                              &image);
  const auto at = [&](double x, double y) {  // glyph coordinates
    return image.at<std::uint8_t>(static_cast<int>(119 - y), static_cast<int>(20 + x));
  };
  EXPECT_EQ(at(48, 75), 255);  // b
  EXPECT_EQ(at(48, 25), 255);  // c
  EXPECT_EQ(at(7, 75), 0);     // f
  EXPECT_EQ(at(27, 50), 0);    // g
  EXPECT_EQ(at(27, 95), 0);    // a
  cv::Mat eight = cv::Mat::zeros(130, 100, CV_8U);
  font::DrawSevenSegmentDigit('8', 100.0, 15.0, {20.0, 119.0}, {1.0, 0.0}, {0.0, -1.0}, 255,
                              &eight);
  // Every segment box of "8" is filled: 3 horizontal, 4 vertical, overlaps
  // at the corners and where g meets the verticals. OpenCV's antialiased
  // fill bleeds up to a pixel beyond the edges (vertices at pixel centres).
  const double area = 3 * 55 * 15 + 4 * 50 * 15 - 4 * 15 * 15 - 2 * 7.5 * 15 - 2 * 7.5 * 15;
  const double outline_px = 4 * 55 + 4 * 100 + 6 * 15;
  EXPECT_GT(cv::sum(eight)[0] / 255.0, area);
  EXPECT_LT(cv::sum(eight)[0] / 255.0, area + outline_px);
  EXPECT_THROW(font::DrawSevenSegmentDigit('8', 10.0, 1.5, {0, 0}, {1, 0}, {0, -1}, 255, nullptr),
               std::invalid_argument);
}

TEST(DigitClassifierTest, TrainingIsDeterministic) {
  DigitTrainingOptions options;
  options.samples_per_class = 30;
  options.epochs = 2;
  const DigitClassifier a = DigitClassifier::Train(options);
  const DigitClassifier b = DigitClassifier::Train(options);
  Random rng(3);
  for (int label = 0; label < kDigitClasses; ++label) {
    const cv::Mat patch = RenderDigitPatch(RandomAugmentation(label, rng), rng);
    EXPECT_EQ(a.Classify(patch), b.Classify(patch));
  }
  EXPECT_EQ(&DigitClassifier::Default(), &DigitClassifier::Default());
}

TEST(DigitClassifierTest, ProbabilitiesSumToOne) {
  Random rng(4);
  const cv::Mat patch = RenderDigitPatch(RandomAugmentation(5, rng), rng);
  const ClassProbabilities p = DigitClassifier::Default().Classify(patch);
  EXPECT_NEAR(std::accumulate(p.begin(), p.end(), 0.0), 1.0, 1e-9);
  for (double v : p) EXPECT_GE(v, 0.0);
}

// Held-out rendered digits (another seed than training's): the digits are
// read right, and the confident answers are more often right than the
// hesitant ones.
TEST(DigitClassifierTest, ReadsHeldOutDigitsWithCalibratedConfidence) {
  const DigitClassifier& classifier = DigitClassifier::Default();
  Random rng(77);
  int digits = 0, digits_right = 0;
  int confident = 0, confident_right = 0, hesitant = 0, hesitant_right = 0;
  for (int i = 0; i < 200 * kDigitClasses; ++i) {
    const int label = i % kDigitClasses;
    const ClassProbabilities p =
        classifier.Classify(RenderDigitPatch(RandomAugmentation(label, rng), rng));
    const int best = ArgMax(p);
    if (label < 10) {
      ++digits;
      digits_right += best == label;
    }
    const double top = p[static_cast<size_t>(best)];
    if (top >= 0.9) {
      ++confident;
      confident_right += best == label;
    } else if (top < 0.7) {
      ++hesitant;
      hesitant_right += best == label;
    }
  }
  const double digit_accuracy = static_cast<double>(digits_right) / digits;
  const double confident_accuracy = static_cast<double>(confident_right) / confident;
  const double hesitant_accuracy = static_cast<double>(hesitant_right) / hesitant;
  RecordProperty("digit_accuracy", std::to_string(digit_accuracy));
  EXPECT_GE(digit_accuracy, 0.98);
  EXPECT_GE(confident_accuracy, 0.95);
  EXPECT_GT(hesitant, 20);
  EXPECT_LT(hesitant_accuracy, 0.85);
}

TEST(DigitClassifierTest, EmptyFloorIsNotADigit) {
  const cv::Mat floor = cv::Mat::zeros(kDigitPatchRows, kDigitPatchCols, CV_32F);
  const ClassProbabilities p = DigitClassifier::Default().Classify(floor);
  EXPECT_EQ(ArgMax(p), kNotADigit);
  EXPECT_GT(p[kNotADigit], 0.8);
}

TEST(DigitClassifierTest, RejectsBadInput) {
  EXPECT_THROW(DigitClassifier::Default().Classify(cv::Mat::zeros(20, 16, CV_32F)),
               std::invalid_argument);
  EXPECT_THROW(DigitClassifier::Default().Classify(cv::Mat::zeros(24, 16, CV_8U)),
               std::invalid_argument);
  Random rng(1);
  EXPECT_THROW(RandomAugmentation(11, rng), std::invalid_argument);
  DigitTrainingOptions options;
  options.epochs = 0;
  EXPECT_THROW(DigitClassifier::Train(options), std::invalid_argument);
}

}  // namespace
}  // namespace parkslam::perception
