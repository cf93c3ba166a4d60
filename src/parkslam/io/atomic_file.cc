#include "parkslam/io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <system_error>

#include "parkslam/io/io_error.h"

namespace parkslam::io {
namespace {

namespace fs = std::filesystem;

std::string ErrnoText(int error_number) {
  return std::generic_category().message(error_number);
}

// A name no other writer in this or another process uses at the same time.
fs::path TemporaryPathFor(const fs::path& path) {
  static std::atomic<unsigned> counter{0};
  fs::path temporary = path;
  temporary += ".tmp." + std::to_string(::getpid()) + "." +
               std::to_string(counter.fetch_add(1));
  return temporary;
}

// Writes all of `content` to the open descriptor; false on failure (errno set).
bool WriteAll(int fd, std::string_view content) {
  const char* data = content.data();
  std::size_t left = content.size();
  while (left > 0) {
    const ssize_t written = ::write(fd, data, left);
    if (written < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    data += written;
    left -= static_cast<std::size_t>(written);
  }
  return true;
}

void CreateParentFolders(const fs::path& path) {
  const fs::path parent = path.parent_path();
  if (parent.empty()) return;
  std::error_code error;
  fs::create_directories(parent, error);
  if (error) {
    ThrowIoError(path.string(), 0, "",
                 "cannot create folder " + parent.string() + ": " +
                     error.message());
  }
}

}  // namespace

void WriteFileAtomically(const fs::path& path, std::string_view content) {
  CreateParentFolders(path);
  const fs::path temporary = TemporaryPathFor(path);
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC,
                        0644);
  if (fd < 0) {
    ThrowIoError(path.string(), 0, "", "cannot create: " + ErrnoText(errno));
  }
  const bool written = WriteAll(fd, content) && ::fsync(fd) == 0;
  const int write_errno = errno;
  const bool closed = ::close(fd) == 0;
  if (!written || !closed) {
    ::unlink(temporary.c_str());
    ThrowIoError(path.string(), 0, "",
                 "cannot write: " + ErrnoText(written ? errno : write_errno));
  }
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    const int rename_errno = errno;
    ::unlink(temporary.c_str());
    ThrowIoError(path.string(), 0, "", "cannot replace: " + ErrnoText(rename_errno));
  }
}

std::string ReadTextFile(const fs::path& path) {
  std::error_code error;
  if (fs::is_directory(path, error)) {
    ThrowIoError(path.string(), 0, "", "is a folder, not a file");
  }
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    ThrowIoError(path.string(), 0, "", "cannot open: " + ErrnoText(errno));
  }
  std::string content;
  struct stat status {};
  if (::fstat(fd, &status) == 0 && status.st_size > 0) {
    content.reserve(static_cast<std::size_t>(status.st_size));
  }
  char buffer[1 << 16];
  while (true) {
    const ssize_t n = ::read(fd, buffer, sizeof(buffer));
    if (n == 0) break;
    if (n < 0) {
      if (errno == EINTR) continue;
      const int read_errno = errno;
      ::close(fd);
      ThrowIoError(path.string(), 0, "", "cannot read: " + ErrnoText(read_errno));
    }
    content.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(fd);
  return content;
}

}  // namespace parkslam::io
