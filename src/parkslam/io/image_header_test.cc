#include "parkslam/io/image_header.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "parkslam/io/io_error.h"

namespace parkslam::io {
namespace {

using ::testing::HasSubstr;

std::string Encoded(const char* ext, const cv::Mat& image) {
  std::vector<uchar> buffer;
  EXPECT_TRUE(cv::imencode(ext, image, buffer));
  return std::string(buffer.begin(), buffer.end());
}

std::string HeaderErrorOf(std::string_view bytes) {
  try {
    ImageSizeFromHeader(bytes, "x.img");
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

TEST(ImageHeaderTest, ReadsTheSizeOfEachFormatWithoutDecoding) {
  const cv::Mat grey(37, 53, CV_8UC1, cv::Scalar(90)), colour(41, 29, CV_8UC3, cv::Scalar(1, 2, 3));
  for (const char* ext : {".png", ".jpg", ".bmp", ".pgm"}) {
    EXPECT_EQ(ImageSizeFromHeader(Encoded(ext, grey), "x"), cv::Size(53, 37)) << ext;
  }
  for (const char* ext : {".png", ".jpg", ".bmp", ".ppm"}) {
    EXPECT_EQ(ImageSizeFromHeader(Encoded(ext, colour), "x"), cv::Size(29, 41)) << ext;
  }
}

TEST(ImageHeaderTest, HugeDeclaredImagesAreRefusedBeforeDecoding) {
  // A PNG header declaring 20000 x 20000 pixels, and nothing else.
  std::string png = Encoded(".png", cv::Mat(1, 1, CV_8UC1, cv::Scalar(0)));
  png[16] = 0;
  png[17] = 0;
  png[18] = 0x4e;
  png[19] = 0x20;  // width 20000
  png[20] = 0;
  png[21] = 0;
  png[22] = 0x4e;
  png[23] = 0x20;  // height 20000
  EXPECT_EQ(ImageSizeFromHeader(png, "x"), cv::Size(20000, 20000));
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("huge_" + std::to_string(::getpid()) + ".png");
  std::ofstream(path, std::ios::binary) << png;
  try {
    CheckImageSize(path);
    ADD_FAILURE() << "not refused";
  } catch (const IoError& e) {
    EXPECT_THAT(e.what(), HasSubstr(path.string() + ": an image of 20000 x 20000 pixels"));
  }
  std::filesystem::remove(path);
}

TEST(ImageHeaderTest, OtherFilesAreNamed) {
  EXPECT_THAT(HeaderErrorOf("hello"), HasSubstr("x.img: not a PNG, JPEG, BMP or binary PNM image"));
  EXPECT_THAT(HeaderErrorOf(std::string("\x89PNG\r\n\x1a\n", 8)), HasSubstr("a PNG cut short"));
  EXPECT_THAT(HeaderErrorOf(std::string("\xff\xd8\xff\xe0\x00\x10", 6)),
              HasSubstr("JPEG cut short"));
}

}  // namespace
}  // namespace parkslam::io
