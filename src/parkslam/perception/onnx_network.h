#ifndef PARKSLAM_PERCEPTION_ONNX_NETWORK_H_
#define PARKSLAM_PERCEPTION_ONNX_NETWORK_H_

// A trained network exported to ONNX (scripts/learned/), run by OpenCV's
// dnn module on the CPU with one thread's worth of work per call. Loading
// checks the file and the shape of the output on a blank input, so that a
// missing, corrupt or mismatched weights file fails at start-up with its
// name, not at the first frame.

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>

namespace parkslam::perception {

class OnnxNetwork {
 public:
  // Loads `path` and checks that an input blob of `input_shape` (N, C, H,
  // W) gives an output of `output_shape`. Throws std::runtime_error naming
  // the file: missing, unreadable, not an ONNX model OpenCV can run, or of
  // other shapes.
  OnnxNetwork(const std::string& path, const std::vector<int>& input_shape,
              const std::vector<int>& output_shape);

  // Runs the network on a blob of the input shape; returns the output
  // (a copy: the network reuses its buffers). Safe to call from several
  // threads (calls are serialized).
  cv::Mat Forward(const cv::Mat& blob) const;

  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::vector<int> input_shape_, output_shape_;
  mutable std::mutex mutex_;
  mutable cv::dnn::Net net_;
};

}  // namespace parkslam::perception

#endif  // PARKSLAM_PERCEPTION_ONNX_NETWORK_H_
