// Fuzzes the files of a dataset folder (docs/dataset_format.md) through
// io::ReadDataset, the reader every command uses. Built three times, by
// PARKSLAM_FUZZ_GROUP: 0 the sensor CSVs, 1 the observation and label JSON
// lines, 2 dataset.yaml (with its scenario), 3 the ground-truth TUM
// trajectory and map JSON. The first byte of an input picks the file of the
// group, the rest replaces it in a valid dataset.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "fuzz/fuzz_util.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/dataset.h"

namespace {
namespace fs = std::filesystem;

const std::vector<std::string>& GroupFiles() {
  static const std::vector<std::vector<std::string>> groups = {
      {"sensors/wheel_speed.csv", "sensors/steering.csv", "sensors/imu.csv"},
      {"observations/slots.jsonl", "observations/tags.jsonl", "groundtruth/slot_labels.jsonl"},
      {"dataset.yaml"},
      {"groundtruth/trajectory.tum", "groundtruth/map.json"}};
  return groups.at(PARKSLAM_FUZZ_GROUP);
}

struct Template {
  fs::path dir;
  std::vector<std::string> originals;  // of GroupFiles()
};

const Template& TheTemplate() {
  static const Template t = [] {
    Template r;
    r.dir = parkslam::fuzz::WriteTemplateDataset("dataset");
    for (const std::string& f : GroupFiles())
      r.originals.push_back(parkslam::io::ReadTextFile(r.dir / f));
    return r;
  }();
  return t;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const Template& t = TheTemplate();
  const std::size_t pick = data[0] % GroupFiles().size();
  const fs::path file = t.dir / GroupFiles()[pick];
  parkslam::fuzz::WriteBytes(file, parkslam::fuzz::AsText(data + 1, size - 1));
  parkslam::fuzz::ExpectAcceptedOrNamedRejection([&] { (void)parkslam::io::ReadDataset(t.dir); },
                                                 GroupFiles()[pick]);
  parkslam::fuzz::WriteBytes(file, t.originals[pick]);
  return 0;
}
