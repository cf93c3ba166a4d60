#include "fuzz/fuzz_util.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include <opencv2/core.hpp>

#include "parkslam/io/atomic_file.h"
#include "parkslam/sim/scenario_config.h"

namespace parkslam::fuzz {
namespace fs = std::filesystem;

const fs::path& ScratchDir() {
  static const fs::path dir = [] {
    const fs::path d = fs::temp_directory_path() / ("parkslam_fuzz_" + std::to_string(::getpid()));
    fs::create_directories(d);
    // Removed at exit; a killed run leaves it in the temporary folder.
    std::atexit([] {
      std::error_code ignored;
      fs::remove_all(fs::temp_directory_path() / ("parkslam_fuzz_" + std::to_string(::getpid())),
                     ignored);
    });
    return d;
  }();
  return dir;
}

void WriteBytes(const fs::path& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) Fail("cannot write " + path.string());
}

void Fail(std::string_view what) {
  std::fprintf(stderr, "FUZZ FINDING: %.*s\n", static_cast<int>(what.size()), what.data());
  std::abort();
}

io::Dataset TemplateDataset() {
  io::Dataset d;
  d.name = "fuzz-template";
  d.seed = 7;
  d.created_by = "parkslam fuzz";
  io::SetScenario(sim::DefaultScenario(), &d);
  SensorLog& log = d.log;
  log.wheel_speeds = {{0, 1.25}, {20'000'000, 1.5}, {40'000'000, 1.5}};
  log.steering_angles = {{0, 0.1}, {20'000'000, -0.3}};
  log.imu_samples = {{0, 0.01, -3.1}, {10'000'000, 0.02, 3.1}};
  SlotObservation slot;
  slot.corners_vehicle = {Eigen::Vector2d(1.0, 1.5), Eigen::Vector2d(3.5, 1.5),
                          Eigen::Vector2d(3.5, 6.8), Eigen::Vector2d(1.0, 6.8)};
  slot.corner_observed = {true, true, false, true};
  slot.corner_sigma_m = 0.03;
  slot.detection_confidence = 0.9;
  slot.id = SlotIdReading{{DigitReading{{{'3', 0.8}, {'8', 0.15}}}, DigitReading{}}};
  log.slot_frames = {{100'000'000, {slot, slot}}, {200'000'000, {}}};
  TagObservation tag;
  tag.tag_id = 7;
  tag.p_vehicle = Eigen::Vector2d(5.1, -0.4);
  tag.range_m = 3.4;
  tag.bearing_rad = -0.1;
  tag.yaw_vehicle_rad = 3.0;
  tag.covariance_vehicle << 0.0004, -0.0001, -0.0001, 0.0009;
  tag.yaw_sigma_rad = 0.03;
  log.tag_frames = {{100'000'000, {tag}}, {250'000'000, {}}};
  d.groundtruth_trajectory = {{0, SE2(-37.0, 9.1, 0.0)}, {10'000'000, SE2(-36.99, 9.1, 0.001)}};
  SemanticMap map;
  map.metadata = {{"source", "fuzz"}};
  MapSlot map_slot;
  map_slot.id = "38";
  map_slot.corners_map = {Eigen::Vector2d(0, 0), Eigen::Vector2d(2.5, 0), Eigen::Vector2d(2.5, 5.3),
                          Eigen::Vector2d(0, 5.3)};
  map.slots.push_back(map_slot);
  d.groundtruth_map = map;
  d.slot_labels = {{0, -1}, {}};
  return d;
}

void WriteHomographyCamera(const fs::path& path) {
  cv::FileStorage out(path.string(), cv::FileStorage::WRITE);
  out << "camera_matrix" << (cv::Mat_<double>(3, 3) << 300, 0, 640, 0, 300, 480, 0, 0, 1);
  out << "dist_coeffs" << (cv::Mat_<double>(4, 1) << 0.01, -0.02, 0.003, -0.001);
  out << "resolution" << (cv::Mat_<int>(2, 1) << 1280, 960);
  out << "project_matrix" << (cv::Mat_<double>(3, 3) << 1, 0.1, 5, 0, 1.2, 7, 0, 0.001, 1);
  out << "scale_xy" << (cv::Mat_<float>(2, 1) << 0.7f, 0.8f);
  out << "shift_xy" << (cv::Mat_<float>(2, 1) << -150.f, -100.f);
}

fs::path WriteTemplateDataset(const std::string& name) {
  const fs::path dir = ScratchDir() / name;
  io::WriteDataset(dir, TemplateDataset());
  fs::create_directories(dir / "images" / "front");
  WriteBytes(dir / "images" / "front" / "100000000.jpg", "");
  WriteBytes(dir / "images" / "front" / "200000000.jpg", "");
  WriteBytes(dir / "images" / "index.csv",
             "t_ns,camera,file\n100000000,front,images/front/100000000.jpg\n"
             "200000000,front,images/front/200000000.jpg\n");
  return dir;
}

}  // namespace parkslam::fuzz
