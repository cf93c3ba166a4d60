#ifndef PARKSLAM_PERCEPTION_DIGIT_CLASSIFIER_H_
#define PARKSLAM_PERCEPTION_DIGIT_CLASSIFIER_H_

// The digit classifier of the slot-ID reader (paper III-A: "the slot ID is
// recognized digit by digit, with confidence"): multinomial logistic
// regression (a softmax over 10 digits and one "not a digit" class) on a
// small normalized patch of one painted seven-segment digit. It is trained
// in-process, deterministically, on digits drawn in the simulator's own font
// (font/digit_font.h) under augmentation that mimics the fused top view:
// scale, stroke, rotation and shear, misalignment, blur (also along one
// direction, as the fisheye's resolution falls with distance), noise,
// contrast and its estimation error, neighbouring digits, and flakes.
// No weights file: the model is rebuilt in well under a second.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <opencv2/core.hpp>

#include "parkslam/common/random.h"

namespace parkslam::perception {

// The classifier's input: CV_32FC1, kDigitPatchRows x kDigitPatchCols,
// the floor at 0 and full paint at 1. The digit box (kDigitWidth x 1 digit
// heights) sits in the middle with margins of kDigitPatchMarginX and
// kDigitPatchMarginY digit heights; a digit height spans
// kDigitPatchPxPerHeight pixels.
inline constexpr int kDigitPatchCols = 16;
inline constexpr int kDigitPatchRows = 24;
inline constexpr double kDigitPatchMarginX = 0.125;
inline constexpr double kDigitPatchMarginY = 0.1;
inline constexpr double kDigitPatchPxPerHeight = kDigitPatchRows / (1.0 + 2 * kDigitPatchMarginY);

inline constexpr int kNotADigit = 10;  // class index of "not a digit"
inline constexpr int kDigitClasses = 11;
using ClassProbabilities = std::array<double, kDigitClasses>;

struct DigitTrainingOptions {
  int samples_per_class = 360;
  int epochs = 12;
  int batch_size = 32;
  double learning_rate = 0.05;
  double l2 = 1e-4;  // weight decay, per sample
  std::uint64_t seed = 20240611;
};

// How one training patch is drawn (exposed for tests). Geometry is in digit
// heights, grey levels in 0..255 before normalization.
struct DigitAugmentation {
  std::uint8_t segments = 0;  // lit segments (font::DigitSegments); 0: none
  double scale_x = 1.0, scale_y = 1.0;
  double rotation_rad = 0.0;
  double shear = 0.0;                                // x += shear * y
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();  // of the digit box, x right, y up
  double stroke = 0.15;
  double floor_grey = 100.0;
  double paint_contrast_grey = 110.0;  // full paint minus floor
  double gradient = 0.0;               // share of the paint contrast gained across the patch
  double gradient_angle_rad = 0.0;
  // Gaussian blur along blur_angle_rad and across it, in patch pixels.
  double blur_major_px = 0.0, blur_minor_px = 0.0, blur_angle_rad = 0.0;
  double noise_grey = 0.0;
  // The reader estimates floor and paint from the whole ID; its estimates
  // are off by these.
  double floor_error_grey = 0.0;
  double contrast_error = 0.0;  // relative
  // Neighbouring digits' lit segments, 0: none.
  std::uint8_t left_segments = 0, right_segments = 0;
  // Round holes in the paint, anywhere in the digit's box.
  int flakes = 0;
  double min_flake_radius = 0.05, max_flake_radius = 0.13;
  // A straight stripe of paint (a line or a stub), 0: none.
  double stripe_width = 0.0, stripe_angle_rad = 0.0;
  Eigen::Vector2d stripe_point = Eigen::Vector2d::Zero();
};

// A random augmentation for a training sample of class `label` (a digit
// 0..9 or kNotADigit).
DigitAugmentation RandomAugmentation(int label, Random& rng);

// Draws a normalized patch under `augmentation`; `rng` gives the noise and
// the flakes' positions and sizes.
cv::Mat RenderDigitPatch(const DigitAugmentation& augmentation, Random& rng);

class DigitClassifier {
 public:
  // Trains on rendered samples; deterministic for given options.
  static DigitClassifier Train(const DigitTrainingOptions& options = {});
  // One classifier per process, trained with the default options on first use.
  static const DigitClassifier& Default();

  // The class probabilities of a normalized patch (see above). Throws
  // std::invalid_argument for a patch of the wrong size or type.
  ClassProbabilities Classify(const cv::Mat& patch) const;

 private:
  static constexpr int kFeatures = kDigitPatchCols * kDigitPatchRows;
  using Weights = Eigen::Matrix<float, kDigitClasses, kFeatures + 1>;  // last column: bias

  DigitClassifier() : weights_(Weights::Zero()) {}
  Weights weights_;
};

}  // namespace parkslam::perception

#endif  // PARKSLAM_PERCEPTION_DIGIT_CLASSIFIER_H_
