#include "parkslam/io/image_folder.h"

#include <system_error>

#include <opencv2/imgcodecs.hpp>

#include "parkslam/camera/image_plane.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/image_header.h"
#include "parkslam/io/io_error.h"
#include "parkslam/io/text_util.h"

namespace parkslam::io {

std::vector<ImageIndexEntry> ReadImageIndex(const std::filesystem::path& dataset_dir) {
  const std::filesystem::path path = dataset_dir / "images" / "index.csv";
  const std::string name = path.string();
  std::error_code error;
  if (!std::filesystem::exists(path, error)) {
    ThrowIoError(name, 0, "", "missing (the dataset has no images: simulate --images writes them)");
  }
  const std::string text = ReadTextFile(path);
  text::LineCursor lines(text);
  std::string_view line;
  if (!lines.Next(&line) || text::Trim(line) != "t_ns,camera,file") {
    ThrowIoError(name, 1, "", "expected the header t_ns,camera,file");
  }
  std::vector<ImageIndexEntry> entries;
  std::map<std::pair<TimeNs, std::string>, int> seen;
  while (lines.Next(&line)) {
    if (text::Trim(line).empty()) continue;
    const int n = lines.line_number();
    std::string_view fields[3];
    if (text::Split(line, ',', fields, 3) != 3) ThrowIoError(name, n, "", "expected 3 fields");
    const std::optional<std::int64_t> t = text::ParseInt64(text::Trim(fields[0]));
    if (!t || *t < 0) ThrowIoError(name, n, "t_ns", "not a non-negative integer");
    if (!entries.empty() && *t < entries.back().t_ns) {
      ThrowIoError(name, n, "t_ns", "earlier than the line before");
    }
    ImageIndexEntry e{*t, std::string(text::Trim(fields[1])), std::string(text::Trim(fields[2]))};
    if (e.camera.empty()) ThrowIoError(name, n, "camera", "empty");
    const std::filesystem::path file(e.file);
    if (e.file.empty() || file.is_absolute() || e.file.find("..") != std::string::npos) {
      ThrowIoError(name, n, "file", "expected a path inside the dataset folder");
    }
    // A name too long for the file system is "no such file" too.
    if (!std::filesystem::exists(dataset_dir / file, error)) {
      ThrowIoError(name, n, "file", (dataset_dir / file).string() + ": no such file");
    }
    if (!seen.emplace(std::make_pair(e.t_ns, e.camera), n).second) {
      ThrowIoError(name, n, "camera", "'" + e.camera + "' twice at the same time");
    }
    entries.push_back(std::move(e));
  }
  if (entries.empty()) ThrowIoError(name, 0, "", "no images listed");
  return entries;
}

ImageFolderSource::ImageFolderSource(SensorSource& inner, const std::filesystem::path& dataset_dir,
                                     const camera::CameraRig& rig, std::vector<std::string> cameras)
    : inner_(inner), dir_(dataset_dir), cameras_(std::move(cameras)) {
  for (const std::string& name : cameras_) {
    bool found = false;
    for (const camera::CameraConfig& c : rig.cameras) {
      if (c.name == name) {
        sizes_[name] = {c.intrinsics.width, c.intrinsics.height};
        found = true;
      }
    }
    if (!found) {
      ThrowIoError((dataset_dir / "images" / "rig.yaml").string(), 0, "cameras",
                   "no camera '" + name + "'");
    }
  }
  for (const ImageIndexEntry& e : ReadImageIndex(dataset_dir)) {
    if (sizes_.count(e.camera) > 0) frames_[e.t_ns][e.camera] = e.file;
  }
  next_ = frames_.begin();
}

CameraFrame ImageFolderSource::ReadFrame(TimeNs t_ns) {
  const auto& files = frames_.at(t_ns);
  CameraFrame frame;
  frame.t_ns = t_ns;
  for (const std::string& name : cameras_) {
    const auto it = files.find(name);
    if (it == files.end()) {
      ThrowIoError((dir_ / "images" / "index.csv").string(), 0, "camera",
                   "no '" + name + "' image at t_ns " + std::to_string(t_ns));
    }
    const std::string path = (dir_ / it->second).string();
    CheckImageSize(path);
    const cv::Mat image = cv::imread(path, cv::IMREAD_GRAYSCALE);
    if (image.empty()) ThrowIoError(path, 0, "", "not a readable image");
    const auto [width, height] = sizes_.at(name);
    if (image.cols != width || image.rows != height) {
      ThrowIoError(path, 0, "",
                   "image is " + std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                       ", camera '" + name + "' " + std::to_string(width) + "x" +
                       std::to_string(height));
    }
    frame.cameras.push_back(name);
    frame.images.push_back(camera::ToImagePlane(image));
  }
  ++frames_read_;
  return frame;
}

std::optional<SensorEvent> ImageFolderSource::Next() {
  if (!pending_ && !inner_done_) {
    pending_ = inner_.Next();
    inner_done_ = !pending_.has_value();
  }
  if (next_ != frames_.end() && (!pending_ || next_->first < EventTime(*pending_))) {
    const TimeNs t = next_->first;
    ++next_;
    return ReadFrame(t);
  }
  std::optional<SensorEvent> event = std::move(pending_);
  pending_.reset();
  return event;
}

}  // namespace parkslam::io
