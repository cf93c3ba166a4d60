#include "parkslam/io/homography_rig.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include <chrono>
#include <string>

#include "parkslam/io/test_util.h"

namespace parkslam::io {
namespace {

using ::testing::HasSubstr;
using testing::ErrorOf;
using testing::TempDir;

// A camera file as OpenCV's FileStorage writes it.
void WriteCamera(const std::filesystem::path& path) {
  cv::FileStorage out(path.string(), cv::FileStorage::WRITE);
  out << "camera_matrix" << (cv::Mat_<double>(3, 3) << 302.5, 0, 496.6, 0, 320.7, 331.2, 0, 0, 1);
  out << "dist_coeffs" << (cv::Mat_<double>(4, 1) << -0.04, 0.02, -0.03, 0.008);
  out << "resolution" << (cv::Mat_<int>(2, 1) << 960, 640);
  out << "project_matrix" << (cv::Mat_<double>(3, 3) << -0.7, -2.55, 708, -0.3, -2.5, 635, 0, -0.004, 1);
  out << "scale_xy" << (cv::Mat_<float>(2, 1) << 0.7f, 0.8f);
  out << "shift_xy" << (cv::Mat_<float>(2, 1) << -150.f, -100.f);
}

void WriteRig(const TempDir& dir) {
  for (const char* name : {"front.yaml", "back.yaml", "left.yaml", "right.yaml"}) {
    WriteCamera(dir / name);
  }
}

TEST(HomographyRigTest, ReadsWhatOpenCvWrites) {
  TempDir dir;
  WriteRig(dir);
  const camera::HomographyRig rig = LoadHomographyRig(dir.path());
  const camera::HomographyCamera& left = rig.cameras[2];
  EXPECT_EQ(left.intrinsics.width, 960);
  EXPECT_EQ(left.intrinsics.height, 640);
  EXPECT_DOUBLE_EQ(left.intrinsics.fx, 302.5);
  EXPECT_DOUBLE_EQ(left.intrinsics.cy, 331.2);
  EXPECT_DOUBLE_EQ(left.intrinsics.distortion[3], 0.008);
  EXPECT_DOUBLE_EQ(left.project_matrix(0, 2), 708);
  EXPECT_DOUBLE_EQ(left.project_matrix(2, 1), -0.004);
  EXPECT_NEAR(left.scale_xy.y(), 0.8, 1e-7);
  EXPECT_DOUBLE_EQ(left.shift_xy.x(), -150.0);
}

// Inputs found by fuzz_homography_rig that made OpenCV's own parser loop
// for ever or ask for gigabytes: each is now a prompt error naming the file.
TEST(HomographyRigTest, CorruptFilesAreRejectedPromptlyWithFileAndField) {
  TempDir dir;
  WriteRig(dir);
  const std::string hang =
      "%YAML:1.0\n---------------- !!ope------------------------------- !!opencv-matrix\n"
      "ncv-matrix\n   roa: [0\xbf[ --100. ]\n";
  const std::string huge =
      "%YAML:1.0\n---\ncamera_matrix: !!opencv-matrix\n   rows: 300000\n   cols: 90000\n"
      "   dt: d\n   data: [ 1 ]\n";
  const auto start = std::chrono::steady_clock::now();
  dir.Write("back.yaml", hang);
  EXPECT_THAT(ErrorOf([&] { LoadHomographyRig(dir.path()); }), HasSubstr("back.yaml"));
  dir.Write("back.yaml", huge);
  EXPECT_THAT(ErrorOf([&] { LoadHomographyRig(dir.path()); }),
              HasSubstr("back.yaml:3: camera_matrix: expected a 3x3 matrix"));
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
  WriteCamera(dir / "back.yaml");

  dir.Write("left.yaml", "camera_matrix: 1\n");
  EXPECT_THAT(ErrorOf([&] { LoadHomographyRig(dir.path()); }),
              HasSubstr("left.yaml:1: not an OpenCV YAML file"));
  WriteCamera(dir / "left.yaml");
  std::string text = ReadTextFile(dir / "right.yaml");
  text.replace(text.find("dt: i"), 5, "dt: q");
  dir.Write("right.yaml", text);
  EXPECT_THAT(ErrorOf([&] { LoadHomographyRig(dir.path()); }),
              HasSubstr("right.yaml:18: resolution.dt: expected d, f or i"));
}

}  // namespace
}  // namespace parkslam::io
