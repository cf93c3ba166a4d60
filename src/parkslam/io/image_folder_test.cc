#include "parkslam/io/image_folder.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "parkslam/io/test_util.h"

namespace parkslam::io {
namespace {

using testing::ErrorOf;
using testing::TempDir;

void WriteIndex(const std::filesystem::path& dir, const std::string& text) {
  std::filesystem::create_directories(dir / "images" / "cam");
  WriteFileAtomically(dir / "images" / "index.csv", text);
}

void WriteImage(const std::filesystem::path& path, int width, int height) {
  cv::imwrite(path.string(), cv::Mat(height, width, CV_8UC1, cv::Scalar(100)));
}

camera::CameraRig OneCameraRig(int width, int height) {
  camera::CameraRig rig;
  camera::CameraConfig c;
  c.name = "cam";
  c.intrinsics.width = width;
  c.intrinsics.height = height;
  rig.cameras.push_back(c);
  return rig;
}

TEST(ImageFolderTest, MergesFramesIntoTheStreamInTimeOrder) {
  TempDir dir;
  WriteIndex(dir.path(), "t_ns,camera,file\n5,cam,images/cam/5.png\n25,cam,images/cam/25.png\n");
  WriteImage(dir.path() / "images/cam/5.png", 8, 6);
  WriteImage(dir.path() / "images/cam/25.png", 8, 6);
  SensorLog log;
  log.wheel_speeds = {{0, 1.0}, {10, 1.0}, {20, 1.0}, {30, 1.0}};
  SensorLogSource inner(log);
  ImageFolderSource source(inner, dir.path(), OneCameraRig(8, 6), {"cam"});
  std::vector<TimeNs> times;
  int frames = 0;
  while (const auto event = source.Next()) {
    times.push_back(EventTime(*event));
    if (const auto* f = std::get_if<CameraFrame>(&*event)) {
      ++frames;
      ASSERT_EQ(f->images.size(), 1u);
      EXPECT_EQ(f->images[0].width, 8);
      EXPECT_EQ((*f->images[0].pixels)[0], 100);
    }
  }
  EXPECT_EQ(frames, 2);
  EXPECT_EQ(times, (std::vector<TimeNs>{0, 5, 10, 20, 25, 30}));
}

TEST(ImageFolderTest, BadIndexAndImagesAreNamed) {
  TempDir dir;
  const std::filesystem::path index = dir.path() / "images" / "index.csv";
  EXPECT_NE(ErrorOf([&] { ReadImageIndex(dir.path()); }).find("index.csv: missing"),
            std::string::npos);
  WriteIndex(dir.path(), "time,camera,file\n");
  EXPECT_NE(ErrorOf([&] { ReadImageIndex(dir.path()); }).find("index.csv:1"), std::string::npos);
  WriteImage(dir.path() / "images/cam/5.png", 8, 6);
  WriteIndex(dir.path(), "t_ns,camera,file\n5,cam,images/cam/5.png\n4,cam,images/cam/5.png\n");
  EXPECT_NE(ErrorOf([&] { ReadImageIndex(dir.path()); }).find("index.csv:3: t_ns"),
            std::string::npos);
  WriteIndex(dir.path(), "t_ns,camera,file\n5,cam,images/cam/6.png\n");
  EXPECT_NE(ErrorOf([&] { ReadImageIndex(dir.path()); }).find("index.csv:2: file"),
            std::string::npos);
  WriteIndex(dir.path(), "t_ns,camera,file\n5,cam,/etc/passwd\n");
  EXPECT_NE(ErrorOf([&] { ReadImageIndex(dir.path()); }).find("inside the dataset"),
            std::string::npos);
  // An image of the wrong size is named when its frame is read.
  WriteIndex(dir.path(), "t_ns,camera,file\n5,cam,images/cam/5.png\n");
  SensorLog log;
  SensorLogSource inner(log);
  ImageFolderSource source(inner, dir.path(), OneCameraRig(10, 6), {"cam"});
  const std::string error = ErrorOf([&] { source.Next(); });
  EXPECT_NE(error.find("5.png: image is 8x6, camera 'cam' 10x6"), std::string::npos) << error;
}

}  // namespace
}  // namespace parkslam::io
