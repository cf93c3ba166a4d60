#ifndef PARKSLAM_FUZZ_FUZZ_UTIL_H_
#define PARKSLAM_FUZZ_FUZZ_UTIL_H_

// Helpers of the libFuzzer targets (docs/robustness.md, "Fuzzing").
//
// Each target feeds its bytes to one parser, the way the program meets
// them: as a file inside a folder laid out as the program expects. The
// parser may accept the bytes or reject them with io::IoError; the target
// aborts (a finding) when anything else escapes, when the program crashes,
// hangs or takes too much memory (libFuzzer's -timeout and -rss_limit_mb),
// and when a rejection does not name the file it rejects.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "parkslam/io/dataset.h"
#include "parkslam/io/io_error.h"

namespace parkslam::fuzz {

// A folder of this process's own, created on first use.
const std::filesystem::path& ScratchDir();

// Writes `bytes` to `path` as they are (not atomically: speed matters here,
// and the folder is the target's own).
void WriteBytes(const std::filesystem::path& path, std::string_view bytes);

// The bytes as a view.
inline std::string_view AsText(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// Runs parse(); an io::IoError is the expected rejection, but its message
// must name `source` (the file or the label the parser was given). Any other
// exception propagates (libFuzzer reports it as a crash).
template <typename F>
void ExpectAcceptedOrNamedRejection(F parse, std::string_view source);

// A small dataset with every kind of record (sensors, observations with
// full, partial and empty ID readings, ground truth), and two camera images
// with their index, written once into ScratchDir()/name. Returns the folder.
std::filesystem::path WriteTemplateDataset(const std::string& name);

// The template dataset in memory.
io::Dataset TemplateDataset();

// A valid camera of a ground-homography rig (io/homography_rig.h), as
// OpenCV's FileStorage writes it.
void WriteHomographyCamera(const std::filesystem::path& path);

// Aborts with a message on stderr.
[[noreturn]] void Fail(std::string_view what);

template <typename F>
void ExpectAcceptedOrNamedRejection(F parse, std::string_view source) {
  try {
    parse();
  } catch (const io::IoError& e) {
    if (std::string_view(e.what()).find(source) == std::string_view::npos) {
      Fail(std::string("rejection does not name ") + std::string(source) + ": " + e.what());
    }
  }
}

}  // namespace parkslam::fuzz

#endif  // PARKSLAM_FUZZ_FUZZ_UTIL_H_
