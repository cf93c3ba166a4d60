#include "parkslam/perception/digit_classifier.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

#include "parkslam/font/digit_font.h"

namespace parkslam::perception {
namespace {

// Training patches are drawn at twice the patch resolution and averaged
// down (cv::INTER_AREA), as the reader samples the top view.
constexpr int kSupersample = 2;
constexpr double kDrawShiftScale = 1 << font::kGlyphDrawShift;

// Digit-to-digit pitch in digit heights: a neighbour's glyph origin lies
// this far to the left or right.
constexpr double kPitch = font::kDigitWidth + font::kDigitGap;

// Normalized values are clamped to this range: paint brighter than the
// estimate, or floor darker than it (stains), carries no extra evidence.
constexpr float kMinValue = -0.5f, kMaxValue = 1.5f;

// The glyph-to-patch map of one augmentation: glyph coordinates (x right,
// y up from the digit's foot-left corner, in digit heights) to supersampled
// pixel coordinates.
struct PatchFrame {
  const DigitAugmentation& a;
  double px_per_height;

  Eigen::Vector2d operator()(double x, double y) const {
    const double qx = x - font::kDigitWidth / 2, qy = y - 0.5;
    const double sx = a.scale_x * qx + a.shear * a.scale_y * qy, sy = a.scale_y * qy;
    const double c = std::cos(a.rotation_rad), s = std::sin(a.rotation_rad);
    const double rx = c * sx - s * sy + a.offset.x(), ry = s * sx + c * sy + a.offset.y();
    const double X = kDigitPatchMarginX + font::kDigitWidth / 2 + rx;  // from the left edge
    const double Y = kDigitPatchMarginY + 0.5 - ry;                    // from the top edge
    return {X * px_per_height - 0.5, Y * px_per_height - 0.5};
  }
};

cv::Mat AnisotropicGaussian(double sigma_major, double sigma_minor, double angle_rad) {
  const double s_major = std::max(sigma_major, 0.2), s_minor = std::max(sigma_minor, 0.2);
  const int half = static_cast<int>(std::ceil(3.0 * std::max(s_major, s_minor)));
  cv::Mat kernel(2 * half + 1, 2 * half + 1, CV_32F);
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  double sum = 0.0;
  for (int v = -half; v <= half; ++v) {
    for (int u = -half; u <= half; ++u) {
      const double a = (c * u + s * v) / s_major, b = (-s * u + c * v) / s_minor;
      const double w = std::exp(-0.5 * (a * a + b * b));
      kernel.at<float>(v + half, u + half) = static_cast<float>(w);
      sum += w;
    }
  }
  kernel /= sum;
  return kernel;
}

// A random set of lit segments that is no digit: 1 to 5 segments.
std::uint8_t RandomNonDigitSegments(Random& rng) {
  while (true) {
    const auto segments = static_cast<std::uint8_t>(1 + rng.Index(127));
    int lit = 0;
    for (int s = 0; s < 7; ++s) lit += (segments >> s) & 1;
    if (lit > 5) continue;
    bool is_digit = false;
    for (char d = '0'; d <= '9'; ++d) is_digit = is_digit || font::DigitSegments(d) == segments;
    if (!is_digit) return segments;
  }
}

std::uint8_t RandomDigitSegments(Random& rng) {
  return font::DigitSegments(static_cast<char>('0' + rng.Index(10)));
}

}  // namespace

DigitAugmentation RandomAugmentation(int label, Random& rng) {
  if (label < 0 || label >= kDigitClasses) throw std::invalid_argument("digit label out of range");
  DigitAugmentation a;
  const double scale = rng.Uniform(0.92, 1.08);
  a.scale_x = scale * rng.Uniform(0.95, 1.05);
  a.scale_y = scale * rng.Uniform(0.95, 1.05);
  // The entrance direction the reader rectifies with is off by a few
  // degrees; the fisheye-to-top-view mapping adds shear.
  a.rotation_rad = rng.Uniform(-0.07, 0.07);
  a.shear = rng.Uniform(-0.08, 0.08);
  a.offset = {rng.Uniform(-0.09, 0.09), rng.Uniform(-0.06, 0.06)};
  a.stroke = rng.Uniform(0.12, 0.19);
  a.floor_grey = rng.Uniform(50.0, 150.0);
  a.paint_contrast_grey = rng.Uniform(35.0, 140.0);
  a.gradient = rng.Uniform(-0.2, 0.2);
  a.gradient_angle_rad = rng.Uniform(0.0, 2 * std::numbers::pi);
  // Far from the car the top view is blurred, more along the fisheye's
  // radial direction than across it.
  a.blur_major_px = rng.Uniform(0.3, 2.0);
  a.blur_minor_px = a.blur_major_px * rng.Uniform(0.3, 1.0);
  a.blur_angle_rad = rng.Uniform(0.0, std::numbers::pi);
  a.noise_grey = a.paint_contrast_grey * rng.Uniform(0.02, 0.12);
  a.floor_error_grey = a.paint_contrast_grey * 0.04 * rng.Gaussian();
  a.contrast_error = rng.Uniform(-0.2, 0.12);
  if (rng.Bernoulli(0.6)) a.left_segments = RandomDigitSegments(rng);
  if (rng.Bernoulli(0.6)) a.right_segments = RandomDigitSegments(rng);
  if (label < 10) {
    a.segments = font::DigitSegments(static_cast<char>('0' + label));
    // A chip or two: still the digit.
    if (rng.Bernoulli(0.25)) {
      a.flakes = 1;
      a.min_flake_radius = 0.04;
      a.max_flake_radius = 0.09;
    }
    return a;
  }
  // "Not a digit": what a cell of a wrong layout, a worn ID or other paint
  // looks like.
  const double kind = rng.Uniform();
  if (kind < 0.2) {
    // Empty floor.
  } else if (kind < 0.55) {
    // A worn digit: flaked beyond reading (render/ground_raster.cc flakes
    // about 30 % of the ID's box in holes of 3 to 8 cm).
    a.segments = RandomDigitSegments(rng);
    a.flakes = 4 + static_cast<int>(rng.Index(6));
  } else if (kind < 0.85) {
    a.segments = RandomNonDigitSegments(rng);
  } else {
    a.segments = rng.Bernoulli(0.5) ? 0 : RandomNonDigitSegments(rng);
    a.stripe_width = rng.Uniform(0.15, 0.3);
    a.stripe_angle_rad = rng.Uniform(0.0, std::numbers::pi);
    a.stripe_point = {rng.Uniform(0.0, font::kDigitWidth), rng.Uniform(0.0, 1.0)};
  }
  return a;
}

cv::Mat RenderDigitPatch(const DigitAugmentation& a, Random& rng) {
  const double px_per_height = kSupersample * kDigitPatchPxPerHeight;
  const cv::Size big(kSupersample * kDigitPatchCols, kSupersample * kDigitPatchRows);
  const PatchFrame frame{a, px_per_height};
  const auto draw = [&](std::uint8_t segments, double x_shift, cv::Mat* mask) {
    font::DrawSevenSegments(
        segments, 1.0, a.stroke, [&](double x, double y) { return frame(x + x_shift, y); }, 255,
        mask);
  };

  cv::Mat mask = cv::Mat::zeros(big, CV_8U);
  draw(a.segments, 0.0, &mask);
  draw(a.left_segments, -kPitch, &mask);
  draw(a.right_segments, kPitch, &mask);
  if (a.stripe_width > 0.0) {
    const Eigen::Vector2d d(std::cos(a.stripe_angle_rad), std::sin(a.stripe_angle_rad));
    const Eigen::Vector2d n(-d.y(), d.x());
    std::array<cv::Point, 4> quad;
    const double h = a.stripe_width / 2;
    const std::array<Eigen::Vector2d, 4> corners = {
        a.stripe_point - 2 * d - h * n, a.stripe_point + 2 * d - h * n,
        a.stripe_point + 2 * d + h * n, a.stripe_point - 2 * d + h * n};
    for (int i = 0; i < 4; ++i) {
      const Eigen::Vector2d p = frame(corners[i].x(), corners[i].y());
      quad[i] = {static_cast<int>(std::lround(p.x() * kDrawShiftScale)),
                 static_cast<int>(std::lround(p.y() * kDrawShiftScale))};
    }
    cv::fillConvexPoly(mask, quad.data(), 4, cv::Scalar(255), cv::LINE_AA, font::kGlyphDrawShift);
  }
  for (int f = 0; f < a.flakes; ++f) {
    const double x = rng.Uniform(-font::kDigitGap / 2, font::kDigitWidth + font::kDigitGap / 2);
    const double y = rng.Uniform(0.0, 1.0);
    const double r = rng.Uniform(a.min_flake_radius, a.max_flake_radius) * px_per_height;
    const Eigen::Vector2d c = frame(x, y);
    cv::circle(mask,
               cv::Point(static_cast<int>(std::lround(c.x() * kDrawShiftScale)),
                         static_cast<int>(std::lround(c.y() * kDrawShiftScale))),
               static_cast<int>(std::lround(r * a.scale_x * kDrawShiftScale)), cv::Scalar(0),
               cv::FILLED, cv::LINE_AA, font::kGlyphDrawShift);
  }

  // Grey levels: floor plus paint, the paint's contrast varying linearly
  // across the patch (uneven light).
  cv::Mat grey(big, CV_32F);
  const double gc = std::cos(a.gradient_angle_rad), gs = std::sin(a.gradient_angle_rad);
  for (int r = 0; r < big.height; ++r) {
    const std::uint8_t* m = mask.ptr<std::uint8_t>(r);
    float* g = grey.ptr<float>(r);
    for (int c = 0; c < big.width; ++c) {
      const double ramp =
          (gc * (c - big.width / 2.0) / big.width + gs * (r - big.height / 2.0) / big.height);
      const double contrast = a.paint_contrast_grey * (1.0 + a.gradient * ramp);
      g[c] = static_cast<float>(a.floor_grey + contrast * m[c] / 255.0);
    }
  }
  const cv::Mat kernel = AnisotropicGaussian(kSupersample * a.blur_major_px,
                                             kSupersample * a.blur_minor_px, a.blur_angle_rad);
  cv::filter2D(grey, grey, -1, kernel, cv::Point(-1, -1), 0.0, cv::BORDER_REPLICATE);
  cv::Mat patch;
  cv::resize(grey, patch, cv::Size(kDigitPatchCols, kDigitPatchRows), 0, 0, cv::INTER_AREA);
  for (int r = 0; r < patch.rows; ++r) {
    float* p = patch.ptr<float>(r);
    for (int c = 0; c < patch.cols; ++c) p[c] += static_cast<float>(rng.Gaussian(a.noise_grey));
  }

  // The reader normalizes by the brightest paint of the whole ID, which
  // blur dims: the peak of a blurred, unbroken "8" drawn alike.
  cv::Mat reference = cv::Mat::zeros(big, CV_8U);
  draw(font::DigitSegments('8'), 0.0, &reference);
  cv::Mat reference_blurred;
  reference.convertTo(reference_blurred, CV_32F, 1.0 / 255.0);
  cv::filter2D(reference_blurred, reference_blurred, -1, kernel);
  double peak = 1.0;
  cv::minMaxLoc(reference_blurred, nullptr, &peak);
  const double floor = a.floor_grey + a.floor_error_grey;
  const double contrast = a.paint_contrast_grey * std::max(peak, 0.1) * (1.0 + a.contrast_error);
  patch = (patch - floor) / contrast;
  cv::min(cv::max(patch, kMinValue), kMaxValue, patch);
  return patch;
}

DigitClassifier DigitClassifier::Train(const DigitTrainingOptions& options) {
  if (options.samples_per_class < 1 || options.epochs < 1 || options.batch_size < 1 ||
      !(options.learning_rate > 0.0) || !(options.l2 >= 0.0)) {
    throw std::invalid_argument("DigitTrainingOptions: invalid");
  }
  using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const int n = options.samples_per_class * kDigitClasses;
  RowMatrix x(n, kFeatures + 1);
  std::vector<int> labels(static_cast<size_t>(n));
  Random rng(options.seed);
  for (int i = 0; i < n; ++i) {
    const int label = i % kDigitClasses;
    const cv::Mat patch = RenderDigitPatch(RandomAugmentation(label, rng), rng);
    for (int r = 0; r < kDigitPatchRows; ++r) {
      for (int c = 0; c < kDigitPatchCols; ++c) {
        x(i, r * kDigitPatchCols + c) = patch.at<float>(r, c);
      }
    }
    x(i, kFeatures) = 1.0f;
    labels[static_cast<size_t>(i)] = label;
  }

  // Mini-batch gradient descent with momentum on the cross entropy of the
  // softmax, a cosine-decaying step and weight decay (not on the bias).
  DigitClassifier model;
  Weights velocity = Weights::Zero();
  std::vector<int> order(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) order[static_cast<size_t>(i)] = i;
  const int batches = (n + options.batch_size - 1) / options.batch_size;
  const int steps = batches * options.epochs;
  RowMatrix batch(options.batch_size, kFeatures + 1);
  Eigen::MatrixXf residual(options.batch_size, kDigitClasses);
  int step = 0;
  for (int epoch = 0; epoch < options.epochs; ++epoch) {
    for (int i = n - 1; i > 0; --i) {
      std::swap(order[static_cast<size_t>(i)], order[rng.Index(static_cast<std::uint64_t>(i) + 1)]);
    }
    for (int b = 0; b < batches; ++b, ++step) {
      const int begin = b * options.batch_size;
      const int size = std::min(options.batch_size, n - begin);
      for (int k = 0; k < size; ++k) batch.row(k) = x.row(order[static_cast<size_t>(begin + k)]);
      const Eigen::MatrixXf logits = batch.topRows(size) * model.weights_.transpose();
      for (int k = 0; k < size; ++k) {
        const float max_logit = logits.row(k).maxCoeff();
        float sum = 0.0f;
        for (int j = 0; j < kDigitClasses; ++j) {
          residual(k, j) = std::exp(logits(k, j) - max_logit);
          sum += residual(k, j);
        }
        residual.row(k) /= sum;
        residual(k, labels[static_cast<size_t>(order[static_cast<size_t>(begin + k)])]) -= 1.0f;
      }
      Weights gradient = residual.topRows(size).transpose() * batch.topRows(size) / size;
      gradient.leftCols(kFeatures) +=
          static_cast<float>(options.l2) * model.weights_.leftCols(kFeatures);
      const double progress = static_cast<double>(step) / steps;
      const auto rate = static_cast<float>(options.learning_rate * 0.5 *
                                           (1.0 + std::cos(std::numbers::pi * progress)));
      velocity = 0.9f * velocity - rate * gradient;
      model.weights_ += velocity;
    }
  }
  return model;
}

const DigitClassifier& DigitClassifier::Default() {
  static const DigitClassifier model = Train();
  return model;
}

ClassProbabilities DigitClassifier::Classify(const cv::Mat& patch) const {
  if (patch.type() != CV_32FC1 || patch.rows != kDigitPatchRows || patch.cols != kDigitPatchCols) {
    throw std::invalid_argument("DigitClassifier: expected a 24x16 CV_32F patch");
  }
  Eigen::Matrix<float, kFeatures + 1, 1> x;
  for (int r = 0; r < kDigitPatchRows; ++r) {
    const float* p = patch.ptr<float>(r);
    for (int c = 0; c < kDigitPatchCols; ++c) {
      x(r * kDigitPatchCols + c) = std::clamp(p[c], kMinValue, kMaxValue);
    }
  }
  x(kFeatures) = 1.0f;
  const Eigen::Matrix<float, kDigitClasses, 1> logits = weights_ * x;
  ClassProbabilities p{};
  const double max_logit = logits.maxCoeff();
  double sum = 0.0;
  for (int j = 0; j < kDigitClasses; ++j) {
    p[static_cast<size_t>(j)] = std::exp(logits(j) - max_logit);
    sum += p[static_cast<size_t>(j)];
  }
  for (double& v : p) v /= sum;
  return p;
}

}  // namespace parkslam::perception
