#include "parkslam/viz/svg.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace parkslam::viz {
namespace {

int CountOf(const std::string& text, const std::string& needle) {
  int count = 0;
  for (size_t at = text.find(needle); at != std::string::npos;
       at = text.find(needle, at + needle.size())) {
    ++count;
  }
  return count;
}

// The map box [0, 10] x [0, 5] at 10 px/m with a 20 px margin: 140 x 90 px.
SvgCanvas SmallCanvas() {
  return SvgCanvas(Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(10.0, 5.0), 10.0, 20.0);
}

TEST(FormatPxTest, RoundsToOneDecimalWithoutTrailingZero) {
  EXPECT_EQ(FormatPx(12.34), "12.3");
  EXPECT_EQ(FormatPx(12.36), "12.4");
  EXPECT_EQ(FormatPx(3.0), "3");
  EXPECT_EQ(FormatPx(2.96), "3");
  EXPECT_EQ(FormatPx(-7.5), "-7.5");
}

TEST(FormatPxTest, WritesNoNegativeZero) { EXPECT_EQ(FormatPx(-0.04), "0"); }

TEST(FormatFixedTest, KeepsRequestedDecimals) {
  EXPECT_EQ(FormatFixed(0.85, 2), "0.85");
  EXPECT_EQ(FormatFixed(0.5, 2), "0.5");
}

TEST(XmlEscapeTest, EscapesSpecialCharacters) {
  EXPECT_EQ(XmlEscape("a<b & 'c' > \"d\""), "a&lt;b &amp; &apos;c&apos; &gt; &quot;d&quot;");
}

TEST(SvgCanvasTest, SizeIsBoxTimesScalePlusMargins) {
  const SvgCanvas canvas = SmallCanvas();
  EXPECT_DOUBLE_EQ(canvas.width_px(), 140.0);
  EXPECT_DOUBLE_EQ(canvas.height_px(), 90.0);
}

TEST(SvgCanvasTest, FlipsTheYAxis) {
  const SvgCanvas canvas = SmallCanvas();
  EXPECT_TRUE(canvas.ToPixel({0.0, 0.0}).isApprox(Eigen::Vector2d(20.0, 70.0)));
  EXPECT_TRUE(canvas.ToPixel({10.0, 5.0}).isApprox(Eigen::Vector2d(120.0, 20.0)));
}

TEST(SvgCanvasTest, ToMapInvertsToPixel) {
  const SvgCanvas canvas = SmallCanvas();
  const Eigen::Vector2d p_map(3.7, -1.2);
  EXPECT_TRUE(canvas.ToMap(canvas.ToPixel(p_map)).isApprox(p_map));
}

TEST(SvgCanvasTest, FinishWritesAStandaloneDocument) {
  const std::string svg = SmallCanvas().Finish();
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_NE(svg.find("xmlns=\"http://www.w3.org/2000/svg\""), std::string::npos);
  EXPECT_NE(svg.find("width=\"140\" height=\"90\""), std::string::npos);
  EXPECT_NE(svg.find("fill=\"white\""), std::string::npos);
  EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
}

TEST(SvgCanvasTest, CircleInPixelCoordinates) {
  SvgCanvas canvas = SmallCanvas();
  canvas.Circle({1.0, 2.0}, 3.0, {.fill = "red"});
  EXPECT_NE(canvas.Finish().find("<circle cx=\"30\" cy=\"50\" r=\"3\" fill=\"red\"/>"),
            std::string::npos);
}

TEST(SvgCanvasTest, PolylinePointsRoundedAndUnfilled) {
  SvgCanvas canvas = SmallCanvas();
  canvas.Polyline({{0.0, 0.0}, {1.234, 0.0}}, {.stroke = "blue"});
  EXPECT_NE(
      canvas.Finish().find("<polyline points=\"20,70 32.3,70\" stroke=\"blue\" fill=\"none\"/>"),
      std::string::npos);
}

TEST(SvgCanvasTest, PolygonCarriesItsStyle) {
  SvgCanvas canvas = SmallCanvas();
  canvas.Polygon(
      {{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}},
      {.stroke = "black", .fill = "#555555", .width_px = 2.0, .dash = "4 3", .opacity = 0.5});
  EXPECT_NE(canvas.Finish().find("<polygon points=\"20,70 30,70 30,60\" stroke=\"black\" "
                                 "fill=\"#555555\" stroke-width=\"2\" stroke-dasharray=\"4 3\" "
                                 "opacity=\"0.5\"/>"),
            std::string::npos);
}

TEST(SvgCanvasTest, RectNormalisesCorners) {
  SvgCanvas canvas = SmallCanvas();
  canvas.Rect({2.0, 3.0}, {1.0, 1.0}, {});
  EXPECT_NE(canvas.Finish().find("<rect x=\"30\" y=\"40\" width=\"10\" height=\"20\"/>"),
            std::string::npos);
}

TEST(SvgCanvasTest, LineEndpoints) {
  SvgCanvas canvas = SmallCanvas();
  canvas.Line({0.0, 5.0}, {10.0, 0.0}, {});
  EXPECT_NE(canvas.Finish().find("<line x1=\"20\" y1=\"20\" x2=\"120\" y2=\"70\"/>"),
            std::string::npos);
}

TEST(SvgCanvasTest, TextIsEscapedAndRotatedAboutItsAnchor) {
  SvgCanvas canvas = SmallCanvas();
  canvas.Text({1.0, 2.0}, "a<b&c", {.font_size_px = 9.0}, 90.0);
  EXPECT_NE(canvas.Finish().find("<text x=\"30\" y=\"50\" "
                                 "transform=\"rotate(90 30 50)\" "
                                 "font-size=\"9\">a&lt;b&amp;c</text>"),
            std::string::npos);
}

TEST(SvgCanvasTest, FinishClosesOpenGroups) {
  SvgCanvas canvas = SmallCanvas();
  canvas.BeginGroup({.stroke = "black"}, "outer");
  canvas.BeginGroup();
  canvas.EndGroup();
  const std::string svg = canvas.Finish();
  EXPECT_NE(svg.find("<g id=\"outer\" stroke=\"black\">"), std::string::npos);
  EXPECT_EQ(CountOf(svg, "<g"), 2);
  EXPECT_EQ(CountOf(svg, "</g>"), 2);
}

TEST(SvgCanvasTest, EndGroupWithoutGroupThrows) {
  SvgCanvas canvas = SmallCanvas();
  EXPECT_THROW(canvas.EndGroup(), std::logic_error);
}

TEST(SvgCanvasTest, RejectsNonPositiveScale) {
  EXPECT_THROW(SvgCanvas(Eigen::Vector2d::Zero(), Eigen::Vector2d::Ones(), 0.0),
               std::invalid_argument);
}

TEST(SvgCanvasTest, RejectsInvertedBox) {
  EXPECT_THROW(SvgCanvas(Eigen::Vector2d::Ones(), Eigen::Vector2d::Zero(), 10.0),
               std::invalid_argument);
}

}  // namespace
}  // namespace parkslam::viz
