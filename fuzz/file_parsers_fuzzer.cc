// Fuzzes the parsers of single files, each the way the program reads it:
// PARKSLAM_FUZZ_PARSER names one of map_json, scenario_yaml, rig_yaml, tum, g2o,
// ps2_labels, numeric_csv, image_index, image_header, homography_rig.
// (The homography rig reads front/back/left/right.yaml of a folder; the
// first byte of an input picks the file, the rest replaces it.)

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "fuzz/fuzz_util.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/g2o.h"
#include "parkslam/io/homography_rig.h"
#include "parkslam/io/image_folder.h"
#include "parkslam/io/image_header.h"
#include "parkslam/io/map_json.h"
#include "parkslam/io/numeric_csv.h"
#include "parkslam/io/ps2_labels.h"
#include "parkslam/io/rig_yaml.h"
#include "parkslam/io/scenario_yaml.h"
#include "parkslam/io/tum.h"

namespace {
namespace fs = std::filesystem;
using parkslam::fuzz::AsText;
using parkslam::fuzz::ExpectAcceptedOrNamedRejection;
using parkslam::fuzz::ScratchDir;
using parkslam::fuzz::WriteBytes;
namespace io = parkslam::io;

constexpr std::string_view kParser = PARKSLAM_FUZZ_PARSER;

constexpr const char* kHomographyFiles[] = {"front.yaml", "back.yaml", "left.yaml", "right.yaml"};

const fs::path& HomographyFolder() {
  static const fs::path dir = [] {
    const fs::path d = ScratchDir() / "homography";
    fs::create_directories(d);
    for (const char* f : kHomographyFiles) parkslam::fuzz::WriteHomographyCamera(d / f);
    return d;
  }();
  return dir;
}

const fs::path& DatasetFolder() {
  static const fs::path dir = parkslam::fuzz::WriteTemplateDataset("dataset");
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text = AsText(data, size);
  if (kParser == "map_json") {
    const fs::path file = ScratchDir() / "map.json";
    WriteBytes(file, text);
    ExpectAcceptedOrNamedRejection([&] { (void)io::ReadMap(file); }, "map.json");
  } else if (kParser == "scenario_yaml") {
    const fs::path file = ScratchDir() / "scenario.yaml";
    WriteBytes(file, text);
    ExpectAcceptedOrNamedRejection([&] { (void)io::LoadScenarioFile(file); }, "scenario.yaml");
  } else if (kParser == "rig_yaml") {
    const fs::path file = ScratchDir() / "rig.yaml";
    WriteBytes(file, text);
    ExpectAcceptedOrNamedRejection([&] { (void)io::LoadRig(file); }, "rig.yaml");
  } else if (kParser == "tum") {
    const fs::path file = ScratchDir() / "poses.tum";
    WriteBytes(file, text);
    ExpectAcceptedOrNamedRejection([&] { (void)io::ReadTum(file); }, "poses.tum");
  } else if (kParser == "g2o") {
    const fs::path file = ScratchDir() / "graph.g2o";
    WriteBytes(file, text);
    ExpectAcceptedOrNamedRejection([&] { (void)io::ReadG2o(file); }, "graph.g2o");
  } else if (kParser == "ps2_labels") {
    const fs::path file = ScratchDir() / "labels.json";
    WriteBytes(file, text);
    ExpectAcceptedOrNamedRejection([&] { (void)io::ReadPs2Labels(file); }, "labels.json");
  } else if (kParser == "numeric_csv") {
    const fs::path file = ScratchDir() / "table.csv";
    WriteBytes(file, text);
    ExpectAcceptedOrNamedRejection([&] { (void)io::ReadNumericCsv(file, {"t_s"}); }, "table.csv");
  } else if (kParser == "image_index") {
    const fs::path file = DatasetFolder() / "images" / "index.csv";
    WriteBytes(file, text);
    ExpectAcceptedOrNamedRejection([&] { (void)io::ReadImageIndex(DatasetFolder()); }, "index.csv");
  } else if (kParser == "image_header") {
    ExpectAcceptedOrNamedRejection([&] { (void)io::ImageSizeFromHeader(text, "image.png"); },
                                   "image.png");
  } else if (kParser == "homography_rig") {
    if (size == 0) return 0;
    const char* name = kHomographyFiles[data[0] % 4];
    const fs::path file = HomographyFolder() / name;
    WriteBytes(file, text.substr(1));
    ExpectAcceptedOrNamedRejection([&] { (void)io::LoadHomographyRig(HomographyFolder()); }, name);
    parkslam::fuzz::WriteHomographyCamera(file);
  } else {
    parkslam::fuzz::Fail("unknown PARKSLAM_FUZZ_PARSER");
  }
  return 0;
}
