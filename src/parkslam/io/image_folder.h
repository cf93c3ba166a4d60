#ifndef PARKSLAM_IO_IMAGE_FOLDER_H_
#define PARKSLAM_IO_IMAGE_FOLDER_H_

// The camera images of a dataset (docs/dataset_format.md): DIR/images/
// holds <camera>/<t_ns>.jpg, index.csv (t_ns,camera,file) and the rig they
// were taken with (rig.yaml). ImageFolderSource merges them, one frame set
// per time, into a sensor stream.

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "parkslam/camera/camera_model.h"
#include "parkslam/sensor/sensor_log.h"

namespace parkslam::io {

struct ImageIndexEntry {
  TimeNs t_ns = 0;
  std::string camera;
  std::string file;  // relative to the dataset folder
};

// Reads DIR/images/index.csv: the exact header, integer non-decreasing
// t_ns, a camera name, a relative file that exists, one entry per camera
// and time. Throws IoError naming the file, the line and the field.
std::vector<ImageIndexEntry> ReadImageIndex(const std::filesystem::path& dataset_dir);

// Passes `inner` through and adds, in time order, one CameraFrame per time
// of the index with the images of `cameras` (grey, read when their frame is
// due). Each image must have its camera's size in `rig`; a missing camera
// at a time, an unreadable image or a wrong size throws IoError naming the
// file. inner must outlive the source.
class ImageFolderSource final : public SensorSource {
 public:
  ImageFolderSource(SensorSource& inner, const std::filesystem::path& dataset_dir,
                    const camera::CameraRig& rig, std::vector<std::string> cameras);
  std::optional<SensorEvent> Next() override;
  int frames_read() const { return frames_read_; }

 private:
  CameraFrame ReadFrame(TimeNs t_ns);

  SensorSource& inner_;
  std::filesystem::path dir_;
  std::vector<std::string> cameras_;
  std::map<std::string, std::pair<int, int>> sizes_;  // camera -> width, height
  // time -> camera -> file
  std::map<TimeNs, std::map<std::string, std::string>> frames_;
  std::map<TimeNs, std::map<std::string, std::string>>::const_iterator next_;
  std::optional<SensorEvent> pending_;
  bool inner_done_ = false;
  int frames_read_ = 0;
};

}  // namespace parkslam::io

#endif  // PARKSLAM_IO_IMAGE_FOLDER_H_
