#include "parkslam/perception/onnx_network.h"

#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace parkslam::perception {
namespace {

std::string ShapeText(const std::vector<int>& shape) {
  std::ostringstream out;
  for (size_t k = 0; k < shape.size(); ++k) out << (k > 0 ? " x " : "") << shape[k];
  return out.str();
}

std::vector<int> ShapeOf(const cv::Mat& m) {
  std::vector<int> shape;
  for (int k = 0; k < m.dims; ++k) shape.push_back(m.size[k]);
  return shape;
}

}  // namespace

OnnxNetwork::OnnxNetwork(const std::string& path, const std::vector<int>& input_shape,
                         const std::vector<int>& output_shape)
    : path_(path), input_shape_(input_shape), output_shape_(output_shape) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw std::runtime_error(path +
                             ": no such weights file (train it with scripts/learned/, or "
                             "pass the path of the committed one under models/)");
  }
  try {
    net_ = cv::dnn::readNetFromONNX(path);
  } catch (const cv::Exception&) {
    throw std::runtime_error(path +
                             ": not a network OpenCV's dnn module can read (a corrupt or "
                             "truncated ONNX file?)");
  }
  if (net_.empty()) throw std::runtime_error(path + ": the ONNX file holds no network");
  net_.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net_.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  cv::Mat out;
  try {
    out = Forward(
        cv::Mat(static_cast<int>(input_shape.size()), input_shape.data(), CV_32F, cv::Scalar(0)));
  } catch (const cv::Exception&) {
    throw std::runtime_error(path + ": the network does not run on an input of " +
                             ShapeText(input_shape));
  }
  if (ShapeOf(out) != output_shape) {
    throw std::runtime_error(path + ": the network's output is " + ShapeText(ShapeOf(out)) +
                             " for an input of " + ShapeText(input_shape) + ", expected " +
                             ShapeText(output_shape));
  }
}

cv::Mat OnnxNetwork::Forward(const cv::Mat& blob) const {
  std::lock_guard<std::mutex> lock(mutex_);
  net_.setInput(blob);
  return net_.forward().clone();
}

}  // namespace parkslam::perception
