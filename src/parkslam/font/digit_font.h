#ifndef PARKSLAM_FONT_DIGIT_FONT_H_
#define PARKSLAM_FONT_DIGIT_FONT_H_

// The seven-segment font of the slot IDs painted on the floor (paper III-A:
// the slot ID is painted inside the slot and read in the top view). One
// definition for the simulator that paints the IDs (ground_raster.cc) and
// for the reader that learns to read them (perception/digit_classifier.cc).
//
// Glyph coordinates: x to the right and y up from the foot-left corner of a
// digit, in the same unit as its height.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <opencv2/core.hpp>

namespace parkslam::font {

// Proportions of a digit, relative to its height.
inline constexpr double kDigitWidth = 0.55;
inline constexpr double kDigitStroke = 0.15;
inline constexpr double kDigitGap = 0.25;  // between neighbouring digits

// Sub-pixel precision of the polygon filling: vertices carry this many
// fractional bits (as OpenCV's `shift`).
inline constexpr int kGlyphDrawShift = 4;

// The segments lit for a digit: bit s is segment s, 0..6 = a (top), b (top
// right), c (bottom right), d (bottom), e (bottom left), f (top left),
// g (middle). 0 for a character that is not a digit.
std::uint8_t DigitSegments(char digit);

// Segment s of a digit box width x height (stroke thick) as
// {x0, x1, y0, y1} in glyph coordinates.
std::array<double, 4> SegmentBox(int segment, double width, double height, double stroke);

// The width of an ID of `characters` digits `height` tall, gaps included.
double IdWidth(int characters, double height);

// Maps glyph coordinates (x, y) to continuous pixel coordinates (column,
// row; integer values are pixel centres) of the target image.
using GlyphToPixel = std::function<Eigen::Vector2d(double x, double y)>;

// Fills every lit segment of `digit` (a box of height x kDigitWidth *
// height, segments `stroke` thick) with `value`, antialiased, into an 8-bit
// single-channel image; segments are drawn one by one, a to g. Nothing is
// drawn for a character that is not a digit.
void DrawSevenSegmentDigit(char digit, double height, double stroke, const GlyphToPixel& to_pixel,
                           double value, cv::Mat* image);

// Fills the segments whose bits are set in `segments` (as DigitSegments
// gives them), the same way; any set of segments, digit or not.
void DrawSevenSegments(std::uint8_t segments, double height, double stroke,
                       const GlyphToPixel& to_pixel, double value, cv::Mat* image);

// The same with an affine map: glyph (x, y) lands on
// foot_left_px + x * x_axis_px + y * y_axis_px.
void DrawSevenSegmentDigit(char digit, double height, double stroke,
                           const Eigen::Vector2d& foot_left_px, const Eigen::Vector2d& x_axis_px,
                           const Eigen::Vector2d& y_axis_px, double value, cv::Mat* image);

}  // namespace parkslam::font

#endif  // PARKSLAM_FONT_DIGIT_FONT_H_
