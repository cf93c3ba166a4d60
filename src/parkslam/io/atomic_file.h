#ifndef PARKSLAM_IO_ATOMIC_FILE_H_
#define PARKSLAM_IO_ATOMIC_FILE_H_

#include <filesystem>
#include <string>
#include <string_view>

namespace parkslam::io {

// Writes `content` to a temporary file in the folder of `path`, flushes it to
// disk and renames it over `path`, so that readers see either the old file or
// the whole new one. Creates missing parent folders. Throws IoError.
void WriteFileAtomically(const std::filesystem::path& path, std::string_view content);

// The whole content of a file. Throws IoError naming the file when it is
// missing, a folder, or cannot be read.
std::string ReadTextFile(const std::filesystem::path& path);

}  // namespace parkslam::io

#endif  // PARKSLAM_IO_ATOMIC_FILE_H_
