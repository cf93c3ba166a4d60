// fuzz_seeds OUT: writes the seed corpora of the fuzz targets, one folder
// per target under OUT, from what the project itself writes (the dataset
// writer, the map, TUM, ps2.0-label, table and rig writers, OpenCV's image
// encoders and FileStorage). scripts/fuzz.sh adds the shipped config files.

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "fuzz/fuzz_util.h"
#include "parkslam/camera/camera_model.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/g2o.h"
#include "parkslam/io/map_json.h"
#include "parkslam/io/numeric_csv.h"
#include "parkslam/io/ps2_labels.h"
#include "parkslam/io/rig_yaml.h"
#include "parkslam/io/scenario_yaml.h"
#include "parkslam/io/tum.h"
#include "parkslam/sim/pose_graph_generator.h"
#include "parkslam/sim/scenario_config.h"

namespace {
namespace fs = std::filesystem;
using parkslam::fuzz::WriteBytes;
namespace io = parkslam::io;

void Seed(const fs::path& out, const std::string& target, const std::string& name,
          const std::string& bytes) {
  fs::create_directories(out / target);
  WriteBytes(out / target / name, bytes);
}

// A file of the template dataset, behind the byte that picks it.
void DatasetSeed(const fs::path& out, const fs::path& dataset, const std::string& target,
                 const std::vector<std::string>& files) {
  for (std::size_t i = 0; i < files.size(); ++i) {
    Seed(out, target, "seed_" + std::to_string(i),
         std::string(1, static_cast<char>(i)) + io::ReadTextFile(dataset / files[i]));
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: fuzz_seeds OUT\n");
    return 2;
  }
  const fs::path out = argv[1];
  const fs::path dataset = parkslam::fuzz::WriteTemplateDataset("seeds");
  DatasetSeed(out, dataset, "fuzz_sensor_csv",
              {"sensors/wheel_speed.csv", "sensors/steering.csv", "sensors/imu.csv"});
  DatasetSeed(
      out, dataset, "fuzz_observations_jsonl",
      {"observations/slots.jsonl", "observations/tags.jsonl", "groundtruth/slot_labels.jsonl"});
  DatasetSeed(out, dataset, "fuzz_dataset_yaml", {"dataset.yaml"});
  DatasetSeed(out, dataset, "fuzz_groundtruth",
              {"groundtruth/trajectory.tum", "groundtruth/map.json"});
  Seed(out, "fuzz_map_json", "template", io::ReadTextFile(dataset / "groundtruth/map.json"));
  Seed(out, "fuzz_tum", "template", io::ReadTextFile(dataset / "groundtruth/trajectory.tum"));
  {
    parkslam::sim::SyntheticGraphOptions graph_options;
    graph_options.poses = 40;
    graph_options.grid_cells = 4;
    parkslam::sim::SyntheticGraph graph = parkslam::sim::MakeSyntheticGraph(graph_options, 1);
    graph.graph.points[1000] = Eigen::Vector2d(1.5, 2.0);
    graph.graph.point_edges.push_back(
        {3, 1000, Eigen::Vector2d(0.5, 1.0), Eigen::Matrix2d::Identity()});
    Seed(out, "fuzz_g2o", "template", io::FormatG2o(graph.graph));
  }
  Seed(out, "fuzz_image_index", "template", io::ReadTextFile(dataset / "images/index.csv"));
  Seed(out, "fuzz_scenario_yaml", "default", io::ScenarioToYaml(parkslam::sim::DefaultScenario()));
  Seed(out, "fuzz_rig_yaml", "default", io::RigToYaml(parkslam::camera::DefaultRig()));

  io::Ps2Labels labels;
  labels.marking_points = {{Eigen::Vector2d(120.5, 300.0), 1.57, true},
                           {Eigen::Vector2d(240.0, 301.5), 1.60, false}};
  labels.slots = {{0, 1, 1, 90.0}};
  Seed(out, "fuzz_ps2_labels", "template", io::Ps2LabelsToJson(labels).dump());

  io::NumericTable table;
  table.columns = {"t_s", "x_m", "nees"};
  table.rows = {{0.0, 1.5, 2.25}, {0.1, 1.625, 3.0}};
  const fs::path table_file = parkslam::fuzz::ScratchDir() / "table.csv";
  io::WriteNumericCsv(table_file, table);
  Seed(out, "fuzz_numeric_csv", "template", io::ReadTextFile(table_file));

  const cv::Mat colour(24, 32, CV_8UC3, cv::Scalar(30, 120, 200));
  const cv::Mat grey(24, 32, CV_8UC1, cv::Scalar(90));
  for (const char* ext : {".png", ".jpg", ".bmp", ".pgm"}) {
    std::vector<unsigned char> bytes;
    cv::imencode(ext, std::string(ext) == ".pgm" ? grey : colour, bytes);
    Seed(out, "fuzz_image_header", std::string("image") + ext,
         std::string(bytes.begin(), bytes.end()));
  }
  // The homography rig target's template writes its own cameras; one seed
  // per file, each the template's front camera.
  const fs::path camera_file = parkslam::fuzz::ScratchDir() / "front.yaml";
  parkslam::fuzz::WriteHomographyCamera(camera_file);
  for (int i = 0; i < 4; ++i) {
    Seed(out, "fuzz_homography_rig", "seed_" + std::to_string(i),
         std::string(1, static_cast<char>(i)) + io::ReadTextFile(camera_file));
  }
  return 0;
}
