#ifndef PARKSLAM_IO_ATOMIC_FILE_H_
#define PARKSLAM_IO_ATOMIC_FILE_H_

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace parkslam::io {

// Writes `content` to a temporary file in the folder of `path`, flushes it to
// disk and renames it over `path`, so that readers see either the old file or
// the whole new one. Creates missing parent folders. Refuses to replace
// anything but a plain file (a device, FIFO, socket or folder at `path`).
// Throws IoError.
//
// The temporary is "<path>.tmp.<pid>.<start>.<serial>.<check>": the pid and
// the start time of the process that writes it, and a check of all parts,
// so that a later write into the folder removes what a killed process left,
// and nothing else (a user's "notes.tmp.1.2" stays).
void WriteFileAtomically(const std::filesystem::path& path, std::string_view content);

// The temporary's name for `path` written by process `pid`, started at
// `start_ticks` (clock ticks since boot, as /proc/PID/stat gives it), as its
// `serial`-th write.
std::filesystem::path TemporaryPathOf(const std::filesystem::path& path, long pid,
                                      unsigned long long start_ticks, unsigned serial);
// This process's start time, as TemporaryPathOf takes it (0 where unknown).
unsigned long long ThisProcessStartTicks();

// A temporary beside `target` for a writer that streams into a file by path
// itself (a ROS bag, an encoder), or fills a folder (a dataset import):
// named as WriteFileAtomically names its own, removed on destruction unless
// Commit() has renamed it over `target` (a folder replaces only a missing or
// empty one), and a file also on SIGINT, SIGTERM and SIGHUP (a folder there
// is left to the next write's sweep, or to the command's own handler). A
// file's target must be missing or a plain file, a folder's missing or a
// folder; throws IoError.
class TemporaryFile {
 public:
  enum class Kind { kFile, kFolder };
  explicit TemporaryFile(std::filesystem::path target, Kind kind = Kind::kFile);
  ~TemporaryFile();
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;

  // Where to write; nothing is created there until the writer does.
  const std::filesystem::path& path() const { return temporary_; }
  // Flushes the written temporary to disk and renames it over the target.
  void Commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path temporary_;
  int slot_ = -1;  // its place in the list the signal handler removes
  bool committed_ = false;
};

// The most bytes an input of each kind may have (docs/plausible_ranges.md,
// "Input sizes"): files are read whole, and what is parsed from them takes
// a few times their size.
inline constexpr std::uintmax_t kMaxInputBytes = 256u << 20;  // CSV, g2o, TUM, bags' parts
inline constexpr std::uintmax_t kMaxJsonBytes = 64u << 20;    // maps, labels, metrics
inline constexpr std::uintmax_t kMaxYamlBytes = 4u << 20;     // options, scenarios, plans, rigs
inline constexpr std::uintmax_t kMaxImageBytes = 64u << 20;   // one image file

// The whole content of a file. Throws IoError naming the file when it is
// missing, a folder, not a plain file (a FIFO or a device: read from, they
// would block or never end), larger than `max_bytes`, or cannot be read.
std::string ReadTextFile(const std::filesystem::path& path,
                         std::uintmax_t max_bytes = kMaxInputBytes);

// The same checks before a reader that opens the file itself (OpenCV's
// imread); returns the file's size.
std::uintmax_t CheckInputFile(const std::filesystem::path& path, std::uintmax_t max_bytes);

}  // namespace parkslam::io

#endif  // PARKSLAM_IO_ATOMIC_FILE_H_
