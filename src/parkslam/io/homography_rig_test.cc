#include "parkslam/io/homography_rig.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include <chrono>
#include <string>

#include "parkslam/io/test_util.h"

namespace parkslam::io {
namespace {

using testing::ErrorOf;
using ::testing::HasSubstr;
using testing::TempDir;

// The matrices of a camera file, as in the real sample.
struct CameraFile {
  cv::Mat camera_matrix = (cv::Mat_<double>(3, 3) << 302.5, 0, 496.6, 0, 320.7, 331.2, 0, 0, 1);
  cv::Mat dist_coeffs = (cv::Mat_<double>(4, 1) << -0.04, 0.02, -0.03, 0.008);
  cv::Mat resolution = (cv::Mat_<int>(2, 1) << 960, 640);
  cv::Mat project_matrix =
      (cv::Mat_<double>(3, 3) << -0.7, -2.55, 708, -0.3, -2.5, 635, 0, -0.004, 1);
  cv::Mat scale_xy = (cv::Mat_<float>(2, 1) << 0.7f, 0.8f);
  cv::Mat shift_xy = (cv::Mat_<float>(2, 1) << -150.f, -100.f);
};

// A camera file as OpenCV's FileStorage writes it.
void WriteCamera(const std::filesystem::path& path, const CameraFile& c = CameraFile()) {
  cv::FileStorage out(path.string(), cv::FileStorage::WRITE);
  out << "camera_matrix" << c.camera_matrix;
  out << "dist_coeffs" << c.dist_coeffs;
  out << "resolution" << c.resolution;
  out << "project_matrix" << c.project_matrix;
  out << "scale_xy" << c.scale_xy;
  out << "shift_xy" << c.shift_xy;
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

// The message of loading a rig whose left camera is `left`.
std::string ErrorWithLeft(const CameraFile& left) {
  TempDir dir;
  WriteRig(dir);
  WriteCamera(dir / "left.yaml", left);
  return ErrorOf([&] { LoadHomographyRig(dir.path()); });
}

// Values beyond the limits of common/plausible_ranges.h, named by file, line
// and matrix element (row by row, as the file holds them).
TEST(HomographyRigTest, ImplausibleValuesAreRejectedNamingLineAndElement) {
  CameraFile c;
  c.camera_matrix.at<double>(0, 0) = 1e308;
  EXPECT_THAT(ErrorWithLeft(c),
              HasSubstr("left.yaml:7: camera_matrix.data[0]: 1e+308 is outside the plausible "
                        "range [1, 100000] px"));
  c = CameraFile();
  c.camera_matrix.at<double>(1, 1) = -320.7;
  EXPECT_THAT(ErrorWithLeft(c), HasSubstr("camera_matrix.data[4]: -320.7 is outside the "
                                          "plausible range [1, 100000] px"));
  c = CameraFile();
  c.camera_matrix.at<double>(1, 2) = 5000;
  EXPECT_THAT(ErrorWithLeft(c), HasSubstr("camera_matrix.data[5]: 5000 is outside the plausible "
                                          "range [-320, 960] px"));
  c = CameraFile();
  c.dist_coeffs.at<double>(3) = -1e9;
  EXPECT_THAT(ErrorWithLeft(c), HasSubstr("dist_coeffs.data[3]: -1e+09 is outside the "
                                          "plausible range [-100, 100]"));
  c = CameraFile();
  c.resolution.at<int>(1) = 100000;
  EXPECT_THAT(ErrorWithLeft(c), HasSubstr("resolution.data[1]: 1e+05 is outside the plausible "
                                          "range [16, 16384] px"));
  c = CameraFile();
  c.resolution = (cv::Mat_<int>(2, 1) << 16000, 16000);
  EXPECT_THAT(ErrorWithLeft(c), HasSubstr("resolution: 16000 x 16000 pixels, beyond the "
                                          "plausible 64000000"));
  c = CameraFile();
  c.scale_xy.at<float>(0) = 0.f;
  EXPECT_THAT(ErrorWithLeft(c), HasSubstr("scale_xy.data[0]: 0 is outside the plausible range "
                                          "[0.01, 100]"));
  c = CameraFile();
  c.shift_xy.at<float>(1) = 1e7f;
  EXPECT_THAT(ErrorWithLeft(c), HasSubstr("shift_xy.data[1]: 1e+07 is outside the plausible "
                                          "range [-16384, 16384] px"));
}

TEST(HomographyRigTest, SingularProjectMatrixIsRejected) {
  CameraFile c;
  c.project_matrix = cv::Mat::zeros(3, 3, CV_64F);
  EXPECT_THAT(ErrorWithLeft(c), HasSubstr("left.yaml:20: project_matrix: singular"));
  // Rank 2: the third row repeats the first.
  c.project_matrix =
      (cv::Mat_<double>(3, 3) << -0.7, -2.55, 708, -0.3, -2.5, 635, -0.7, -2.55, 708);
  EXPECT_THAT(ErrorWithLeft(c), HasSubstr("left.yaml:20: project_matrix: singular"));
  // A homography is defined up to scale: a tiny multiple is still one.
  c.project_matrix = CameraFile().project_matrix * 1e-6;
  EXPECT_EQ(ErrorWithLeft(c), "");
}

}  // namespace
}  // namespace parkslam::io
