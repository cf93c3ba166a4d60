#include "parkslam/scene/font_book.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace parkslam::scene {
namespace {

TEST(FontBookTest, StrokeFontsAreAlwaysThere) {
  FontBook book({});
  EXPECT_EQ(book.file_count(), 0);
  ASSERT_GE(book.size(), 1);
  const cv::Mat mask = book.Draw("A12", 0, 40.0);
  ASSERT_FALSE(mask.empty());
  EXPECT_EQ(mask.type(), CV_8UC1);
  EXPECT_GT(cv::countNonZero(mask), 100);
  // The text's height is the cap height asked for, plus the margins.
  EXPECT_NEAR(mask.rows, 40 + 2 * 10, 2);
}

TEST(FontBookTest, SystemFontsDrawDigitsAtTheirCapHeight) {
  const std::vector<std::filesystem::path> files = FindFloorFonts();
  if (files.empty())
    GTEST_SKIP()
        << "no font packages under /usr/share/fonts (scripts/install_deps.sh installs them)";
  for (const auto& f : files) {
    const std::string name = f.filename().string();
    EXPECT_EQ(name.find("Italic"), std::string::npos) << name;
    EXPECT_EQ(name.find("Oblique"), std::string::npos) << name;
  }
  FontBook book(files);
  for (int font = 0; font < std::min(book.file_count(), 12); ++font) {
    const cv::Mat mask = book.Draw("208", font, 40.0);
    cv::Mat ink;
    cv::threshold(mask, ink, 128, 255, cv::THRESH_BINARY);
    const cv::Rect box = cv::boundingRect(ink);
    // Digits stand about the cap height tall (fonts differ by a few pixels).
    EXPECT_NEAR(box.height, 40, 8) << files[static_cast<size_t>(font)];
    EXPECT_GT(box.width, 30) << files[static_cast<size_t>(font)];
  }
}

TEST(FontBookTest, SevenSegmentDigitsAreTheDefaultLotsGlyphs) {
  const cv::Mat eight = FontBook::DrawSevenSegment("8", 40.0);
  const cv::Mat one = FontBook::DrawSevenSegment("1", 40.0);
  ASSERT_EQ(eight.type(), CV_8UC1);
  cv::Mat ink;
  cv::threshold(eight, ink, 128, 255, cv::THRESH_BINARY);
  const cv::Rect box = cv::boundingRect(ink);
  // font/digit_font.h: a digit is 0.55 of its height wide.
  EXPECT_NEAR(box.height, 40, 2);
  EXPECT_NEAR(box.width, 22, 2);
  // An 8 lights all seven segments, a 1 two of them.
  EXPECT_GT(cv::countNonZero(eight), 2 * cv::countNonZero(one));
  // Three digits are three cells wide; a letter leaves its cell blank.
  const cv::Mat three = FontBook::DrawSevenSegment("208", 40.0);
  EXPECT_GT(three.cols, 3 * 22);
  EXPECT_EQ(cv::countNonZero(FontBook::DrawSevenSegment("AB", 40.0)), 0);
}

TEST(FontBookTest, FindsNothingInAMissingFolder) {
  EXPECT_TRUE(FindFloorFonts("/nonexistent/fonts").empty());
}

}  // namespace
}  // namespace parkslam::scene
