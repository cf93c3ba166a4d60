#ifndef PARKSLAM_IO_OUTPUT_GUARD_H_
#define PARKSLAM_IO_OUTPUT_GUARD_H_

// An output never replaces an input. Commands name their outputs and
// inputs; before anything is written, every output is compared with every
// input by resolved path and by file identity (a link, `..` or another
// spelling of the same file is the same file):
// - an output file may not be an input file;
// - an output may not lie inside an input folder (a dataset);
// - an output folder may not hold an input (it may be cleared or filled).
// Inputs that do not exist are left to the reader's own error. Outputs are
// also checked against each other (no two name the same file) and against
// what stands at their place (never a device, FIFO or socket). A file
// output must be one that can be written: not a folder, not a path ending
// in "/", its folder a folder that exists or can be made, and writable, so
// that a command never writes one output and then fails on the next.

#include <filesystem>
#include <string>
#include <vector>

namespace parkslam::io {

struct NamedPath {
  std::filesystem::path path;
  std::string name;     // how the user gave it: "--out", "DIR", "--map"
  bool folder = false;  // an output folder (a dataset's), not a file
};

// Throws IoError naming both, e.g.
//   "--out ds/dataset.yaml: lies inside the input DIR ds (an output never
//    replaces or goes into an input)".
void CheckOutputsSpareInputs(const std::vector<NamedPath>& outputs,
                             const std::vector<NamedPath>& inputs);

}  // namespace parkslam::io

#endif  // PARKSLAM_IO_OUTPUT_GUARD_H_
