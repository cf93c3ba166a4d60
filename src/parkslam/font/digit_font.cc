#include "parkslam/font/digit_font.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace parkslam::font {
namespace {

constexpr std::array<std::uint8_t, 10> kDigitSegments = {0b0111111, 0b0000110, 0b1011011, 0b1001111,
                                                         0b1100110, 0b1101101, 0b1111101, 0b0000111,
                                                         0b1111111, 0b1101111};

constexpr double kDrawScale = 1 << kGlyphDrawShift;

cv::Point Fixed(const Eigen::Vector2d& px) {
  return {static_cast<int>(std::lround(px.x() * kDrawScale)),
          static_cast<int>(std::lround(px.y() * kDrawScale))};
}

}  // namespace

std::uint8_t DigitSegments(char digit) {
  if (digit < '0' || digit > '9') return 0;
  return kDigitSegments[static_cast<size_t>(digit - '0')];
}

std::array<double, 4> SegmentBox(int segment, double width, double height, double stroke) {
  const double w = width, h = height, t = stroke;
  switch (segment) {
    case 0:
      return {0, w, h - t, h};
    case 1:
      return {w - t, w, h / 2, h};
    case 2:
      return {w - t, w, 0, h / 2};
    case 3:
      return {0, w, 0, t};
    case 4:
      return {0, t, 0, h / 2};
    case 5:
      return {0, t, h / 2, h};
    default:
      return {0, w, h / 2 - t / 2, h / 2 + t / 2};
  }
}

double IdWidth(int characters, double height) {
  if (characters <= 0) return 0.0;
  const double n = characters;
  return height * (n * kDigitWidth + (n - 1) * kDigitGap);
}

void DrawSevenSegmentDigit(char digit, double height, double stroke, const GlyphToPixel& to_pixel,
                           double value, cv::Mat* image) {
  DrawSevenSegments(DigitSegments(digit), height, stroke, to_pixel, value, image);
}

void DrawSevenSegments(std::uint8_t segments, double height, double stroke,
                       const GlyphToPixel& to_pixel, double value, cv::Mat* image) {
  // OpenCV antialiases polygons in 8-bit images only.
  if (image == nullptr || image->type() != CV_8UC1) {
    throw std::invalid_argument("DrawSevenSegments: expected an 8-bit grey image");
  }
  const double width = kDigitWidth * height;
  for (int s = 0; s < 7; ++s) {
    if (!(segments & (1 << s))) continue;
    const auto [x0, x1, y0, y1] = SegmentBox(s, width, height, stroke);
    const std::array<cv::Point, 4> corners = {Fixed(to_pixel(x0, y0)), Fixed(to_pixel(x1, y0)),
                                              Fixed(to_pixel(x1, y1)), Fixed(to_pixel(x0, y1))};
    cv::fillConvexPoly(*image, corners.data(), 4, cv::Scalar(value), cv::LINE_AA, kGlyphDrawShift);
  }
}

void DrawSevenSegmentDigit(char digit, double height, double stroke,
                           const Eigen::Vector2d& foot_left_px, const Eigen::Vector2d& x_axis_px,
                           const Eigen::Vector2d& y_axis_px, double value, cv::Mat* image) {
  DrawSevenSegmentDigit(
      digit, height, stroke,
      [&](double x, double y) -> Eigen::Vector2d {
        return foot_left_px + x * x_axis_px + y * y_axis_px;
      },
      value, image);
}

}  // namespace parkslam::font
