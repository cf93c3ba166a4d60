#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "commands.h"
#include "image_files.h"
#include "parkslam/common/lot_constants.h"
#include "parkslam/common/plausible_ranges.h"
#include "parkslam/io/rig_yaml.h"
#include "parkslam/perception/tag_detector.h"

namespace parkslam::app {

void AddTagsCommand(CLI::App& app) {
  struct Options {
    std::string image, camera = "default", camera_name;
    double tag_size_m = kDefaultTagSize_m;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "tags",
      "Detect AprilTags (tag36h11) in a front-camera image and locate them by PnP checked by "
      "the direct angle (the paper's III-B)");
  cmd->add_option("--image", options->image, "Image (grey or colour)")->required();
  cmd->add_option("--camera", options->camera,
                  "Camera: `default` (the built-in front camera) or a rig YAML file whose "
                  "pinhole camera is used (or the one named by --camera-name)")
      ->capture_default_str();
  cmd->add_option("--camera-name", options->camera_name, "Camera of the rig file to use");
  cmd->add_option("--tag-size-m", options->tag_size_m, "Edge of the tags' black square")
      ->check(CLI::PositiveNumber)
      ->check(CLI::Range(0.0, kMaxTagSize_m))
      ->capture_default_str();
  cmd->add_flag("--json", options->json, "Print one JSON object");
  cmd->callback([options] {
    const camera::CameraRig rig =
        options->camera == "default" ? camera::DefaultRig() : io::LoadRig(options->camera);
    const camera::CameraConfig* camera = nullptr;
    for (const camera::CameraConfig& c : rig.cameras) {
      const bool named = options->camera_name.empty()
                             ? c.intrinsics.kind == camera::CameraKind::kPinhole
                             : c.name == options->camera_name;
      if (named) {
        camera = &c;
        break;
      }
    }
    if (camera == nullptr) {
      throw std::runtime_error(options->camera + ": no " +
                               (options->camera_name.empty()
                                    ? "pinhole camera"
                                    : "camera '" + options->camera_name + "'"));
    }
    if (!std::filesystem::exists(options->image)) {
      throw std::runtime_error(options->image + ": no such file");
    }
    const cv::Mat grey = ReadImage(options->image, cv::IMREAD_GRAYSCALE);
    if (grey.empty()) throw std::runtime_error(options->image + ": not a readable image");
    perception::TagDetectorOptions detector_options;
    detector_options.tag_size_m = options->tag_size_m;
    const perception::TagDetector detector(detector_options);
    std::vector<perception::DetectedTag> tags;
    try {
      tags = detector.Detect(grey, &camera->intrinsics);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(options->image + ": " + e.what());
    }
    nlohmann::json j = {{"tags", nlohmann::json::array()}};
    for (const perception::DetectedTag& t : tags) {
      nlohmann::json corners = nlohmann::json::array();
      for (const auto& c : t.corners_px) corners.push_back({c.x(), c.y()});
      j["tags"].push_back({{"id", t.tag_id},
                           {"corners_px", corners},
                           {"center_px", {t.center_px.x(), t.center_px.y()}},
                           {"distance_m", t.distance_m},
                           {"alpha_rad", t.alpha_rad},
                           {"x_m", t.position_m.x()},
                           {"y_m", t.position_m.y()},
                           {"hamming", t.hamming}});
    }
    if (options->json) {
      std::cout << j.dump() << "\n";
      return;
    }
    std::printf("%zu tags\n", tags.size());
    for (const perception::DetectedTag& t : tags) {
      std::printf("tag %d: %.2f m, alpha %.2f deg, at x %.2f m (right), y %.2f m (ahead)\n",
                  t.tag_id, t.distance_m, t.alpha_rad * 180.0 / M_PI, t.position_m.x(),
                  t.position_m.y());
    }
  });
}

}  // namespace parkslam::app
