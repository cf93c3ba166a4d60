#include "parkslam/perception/tag_detector.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "parkslam/render/renderer.h"
#include "parkslam/sim/scenario_config.h"
#include "parkslam/sim/world.h"

namespace parkslam::perception {
namespace {

std::filesystem::path DataDir() {
  const char* root = std::getenv("PARKSLAM_SHARED_DATA");
  return std::filesystem::path(root != nullptr ? root : "../shared/data") / "apriltag-test";
}

// Reference corners: one line per tag, "id, (x y), (x y), (x y), (x y)" in
// libapriltag's own pixel convention.
std::vector<std::array<Eigen::Vector2d, 4>> ReadReference(const std::filesystem::path& file) {
  std::vector<std::array<Eigen::Vector2d, 4>> tags;
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    int id = 0;
    std::array<Eigen::Vector2d, 4> c;
    if (std::sscanf(line.c_str(), "%d, (%lf %lf), (%lf %lf), (%lf %lf), (%lf %lf)", &id, &c[0].x(),
                    &c[0].y(), &c[1].x(), &c[1].y(), &c[2].x(), &c[2].y(), &c[3].x(),
                    &c[3].y()) == 9) {
      tags.push_back(c);
    }
  }
  return tags;
}

TEST(TagDetectorTest, RealPhotosMatchTheReferenceCorners) {
  if (!std::filesystem::exists(DataDir())) {
    GTEST_SKIP() << "real data not found at " << DataDir() << " (shared/data absent)";
  }
  TagDetectorOptions options;
  options.quad_decimate = 1.0f;  // as the reference was made
  options.refine_edges = false;
  options.max_hamming = 2;  // libapriltag's default, as the reference
  const TagDetector detector(options);
  int reference_tags = 0, matched = 0;
  double worst = 0.0;
  for (const auto& entry : std::filesystem::directory_iterator(DataDir())) {
    if (entry.path().extension() != ".jpg") continue;
    const cv::Mat grey = cv::imread(entry.path().string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(grey.empty()) << entry.path();
    const std::vector<DetectedTag> tags = detector.Detect(grey);
    for (const auto& reference :
         ReadReference(std::filesystem::path(entry.path()).replace_extension(".txt"))) {
      ++reference_tags;
      for (const DetectedTag& tag : tags) {
        // Ours are 0.5 px smaller (the project's pixel convention).
        if ((tag.corners_px[0] + Eigen::Vector2d(0.5, 0.5) - reference[0]).norm() > 2.0) continue;
        ++matched;
        EXPECT_EQ(tag.tag_id, 0);
        for (int k = 0; k < 4; ++k) {
          worst = std::max(worst,
                           (tag.corners_px[k] + Eigen::Vector2d(0.5, 0.5) - reference[k]).norm());
        }
        break;
      }
    }
  }
  EXPECT_EQ(reference_tags, 47);
  EXPECT_EQ(matched, 47);
  EXPECT_LT(worst, 0.25);
}

TEST(TagDetectorTest, RenderedTagsGiveTheirIdAndDistance) {
  const sim::World world = sim::BuildWorld(sim::DefaultScenario().world, 1);
  const camera::CameraRig rig = camera::DefaultRig();
  const render::Renderer renderer(world, rig, {}, 1);
  const camera::CameraConfig& mono = *rig.Find("front_mono");
  const TagDetector detector;
  // In the corridor, looking east along it.
  const SE2 T_map_vehicle(-30.0, 9.1, 0.0);
  const std::vector<DetectedTag> tags =
      detector.Detect(renderer.Render("front_mono", T_map_vehicle, 0), &mono.intrinsics);
  ASSERT_GE(tags.size(), 2u);
  const Eigen::Isometry3d T_map_camera =
      render::VehiclePose3d(T_map_vehicle) * mono.T_vehicle_camera;
  for (const DetectedTag& tag : tags) {
    ASSERT_GE(tag.tag_id, 0);
    ASSERT_LT(tag.tag_id, static_cast<int>(world.tags.size()));
    const Eigen::Vector3d truth_camera =
        T_map_camera.inverse() * render::TagCenter3d(world.tags[tag.tag_id], renderer.options());
    EXPECT_NEAR(tag.distance_m, truth_camera.norm(), 0.05 * truth_camera.norm()) << tag.tag_id;
    EXPECT_NEAR(tag.alpha_rad, std::atan2(truth_camera.x(), truth_camera.z()), 0.01);
    EXPECT_LT(tag.distance_m, 20.0);
  }
}

TEST(TagDetectorTest, WrongImageIsRejected) {
  const TagDetector detector;
  const camera::CameraRig rig = camera::DefaultRig();  // alive while `mono` is used
  const camera::CameraIntrinsics& mono = rig.Find("front_mono")->intrinsics;
  EXPECT_THROW(detector.Detect(cv::Mat(10, 10, CV_8UC3), nullptr), std::invalid_argument);
  EXPECT_THROW(detector.Detect(cv::Mat(480, 640, CV_8UC1, cv::Scalar(0)), &mono),
               std::invalid_argument);
  EXPECT_TRUE(detector.Detect(cv::Mat(720, 1280, CV_8UC1, cv::Scalar(128)), &mono).empty());
}

TEST(TagDetectorTest, InvalidOptionsThrow) {
  TagDetectorOptions options;
  options.tag_size_m = 0.0;
  EXPECT_THROW(TagDetector{options}, std::invalid_argument);
}

}  // namespace
}  // namespace parkslam::perception
