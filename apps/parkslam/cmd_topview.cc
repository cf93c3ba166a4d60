#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

#include "commands.h"
#include "image_files.h"
#include "parkslam/camera/camera_names.h"
#include "parkslam/camera/homography_top_view.h"
#include "parkslam/camera/top_view.h"
#include "parkslam/common/enum_names.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/homography_rig.h"
#include "parkslam/io/output_guard.h"
#include "parkslam/io/rig_yaml.h"

namespace parkslam::app {
void AddTopviewCommand(CLI::App& app) {
  struct Options {
    std::string rig = "default", front, rear, left, right, out;
    int size_px = 600;
    double extent_m = 10.0;
    std::string seams = "optical_axis";
  };
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "topview",
      "Fuse four fisheye images into one top-view image (surround view). --rig is the built-in "
      "rig `default`, a rig YAML file (docs/cameras.md), or a folder calibrated by ground "
      "homographies (front/back/left/right.yaml, as shared/data/surround-view-sample)");
  cmd->add_option("--rig", options->rig, "Rig: default, RIG.yaml or a folder")
      ->capture_default_str();
  cmd->add_option("--front", options->front, "Front fisheye image")->required();
  cmd->add_option("--rear", options->rear, "Rear fisheye image")->required();
  cmd->add_option("--left", options->left, "Left fisheye image")->required();
  cmd->add_option("--right", options->right, "Right fisheye image")->required();
  cmd->add_option("--out", options->out, "Top-view image to write (PNG or JPEG)")->required();
  cmd->add_option("--size-px", options->size_px, "Top-view size (rig form)")
      ->check(CLI::Range(16, 4096))
      ->capture_default_str();
  cmd->add_option("--extent-m", options->extent_m, "Ground covered (rig form)")
      ->check(CLI::Range(1.0, 100.0))
      ->capture_default_str();
  cmd->add_option("--seams", options->seams,
                  "Where the seams lie (rig form; docs/cameras.md): optical_axis, each ground "
                  "point from the camera nearest its axis; footprint_rays, straight seams from "
                  "the car's corners")
      ->check(CLI::IsMember(EnumNameList<camera::SeamStyle>()))
      ->capture_default_str();
  cmd->callback([options] {
    io::CheckOutputsSpareInputs(
        {{options->out, "--out"}},
        {{options->front, "--front"},
         {options->rear, "--rear"},
         {options->left, "--left"},
         {options->right, "--right"},
         {options->rig == "default" ? std::string() : options->rig, "--rig"}});
    cv::Mat top;
    if (std::filesystem::is_directory(options->rig)) {
      const camera::HomographyTopView view(io::LoadHomographyRig(options->rig));
      top = view.Fuse({ReadImage(options->front, cv::IMREAD_COLOR),
                       ReadImage(options->rear, cv::IMREAD_COLOR),
                       ReadImage(options->left, cv::IMREAD_COLOR),
                       ReadImage(options->right, cv::IMREAD_COLOR)});
    } else {
      const camera::CameraRig rig =
          options->rig == "default" ? camera::DefaultRig() : io::LoadRig(options->rig);
      camera::TopViewOptions view;
      view.size_px = options->size_px;
      view.extent_m = options->extent_m;
      view.seam_style = *EnumFromName<camera::SeamStyle>(options->seams);  // checked above
      const camera::TopViewFusion fusion(rig, camera::FisheyeCameraNames(), view);
      std::vector<cv::Mat> images;
      for (const std::string* path :
           {&options->front, &options->rear, &options->left, &options->right}) {
        images.push_back(ReadImage(*path, cv::IMREAD_GRAYSCALE));
      }
      top = fusion.Fuse(images);
    }
    WriteImage(options->out, top);
    std::printf("wrote %s (%dx%d)\n", options->out.c_str(), top.cols, top.rows);
  });
}

}  // namespace parkslam::app
