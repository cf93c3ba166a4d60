// Surround-view fusion of one 600x600 top view from four 640x480 fisheye
// images (goal: at most 3 ms on one core).

#include <benchmark/benchmark.h>

#include <opencv2/core.hpp>

#include "parkslam/camera/camera_names.h"
#include "parkslam/camera/top_view.h"
#include "parkslam/common/random.h"

namespace parkslam {
namespace {

void BM_FuseTopView(benchmark::State& state) {
  const camera::CameraRig rig = camera::DefaultRig();
  const std::vector<std::string>& names = camera::FisheyeCameraNames();
  const camera::TopViewFusion fusion(rig, names);
  std::vector<cv::Mat> images;
  for (int c = 0; c < 4; ++c) {
    cv::Mat image(480, 640, CV_8UC1);
    cv::randu(image, 0, 255);
    images.push_back(image);
  }
  for (auto _ : state) {
    cv::Mat top = fusion.Fuse(images);
    benchmark::DoNotOptimize(top.data);
  }
}
BENCHMARK(BM_FuseTopView)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace parkslam
