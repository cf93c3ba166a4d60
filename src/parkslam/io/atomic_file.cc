#include "parkslam/io/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <mutex>
#include <set>
#include <system_error>

#include "parkslam/io/io_error.h"

namespace parkslam::io {
namespace {

namespace fs = std::filesystem;

std::string ErrnoText(int error_number) { return std::generic_category().message(error_number); }

// Temporaries being written, so that SIGINT, SIGTERM and SIGHUP remove
// them before the process ends (a killed run leaves no *.tmp.* litter):
// fixed slots of plain characters, as a signal handler may only read
// memory and call unlink().
constexpr int kTemporarySlots = 64;
constexpr std::size_t kSlotBytes = 4096;
std::array<std::atomic<bool>, kTemporarySlots> g_slot_claimed{};  // owned by a writer
std::array<std::atomic<bool>, kTemporarySlots> g_slot_visible{};  // its path is complete
std::array<std::array<char, kSlotBytes>, kTemporarySlots> g_slot_path{};

extern "C" void RemoveTemporariesAndDie(int signal_number) {
  for (int k = 0; k < kTemporarySlots; ++k) {
    if (g_slot_visible[k].load()) ::unlink(g_slot_path[k].data());
  }
  ::signal(signal_number, SIG_DFL);
  ::raise(signal_number);
}

void InstallCleanupOnce() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
      struct sigaction action {};
      struct sigaction previous {};
      ::sigaction(signal_number, nullptr, &previous);
      // Leave a handler the program installed itself alone.
      if (previous.sa_handler != SIG_DFL) continue;
      action.sa_handler = RemoveTemporariesAndDie;
      ::sigemptyset(&action.sa_mask);
      ::sigaction(signal_number, &action, nullptr);
    }
  });
}

// The slot holding `temporary`, or -1 when all are taken or the path is too
// long (then a signal leaves it, and the next write removes it as stale).
int Register(const fs::path& temporary) {
  const std::string& text = temporary.native();
  if (text.size() + 1 > kSlotBytes) return -1;
  for (int k = 0; k < kTemporarySlots; ++k) {
    bool expected = false;
    if (!g_slot_claimed[k].compare_exchange_strong(expected, true)) continue;
    std::memcpy(g_slot_path[k].data(), text.c_str(), text.size() + 1);
    g_slot_visible[k].store(true);
    return k;
  }
  return -1;
}

void Unregister(int slot) {
  if (slot < 0) return;
  g_slot_visible[slot].store(false);
  g_slot_claimed[slot].store(false);
}

// Temporaries of `path` left by a process that no longer runs (killed
// with SIGKILL, or a power cut): "<name>.tmp.<pid>.<n>" with no such pid.
// Each folder is looked through once per process.
void RemoveStaleTemporaries(const fs::path& path) {
  static std::mutex mutex;
  static std::set<fs::path> seen;
  const fs::path folder = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (!seen.insert(folder).second) return;
  }
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const size_t at = name.rfind(".tmp.");
    if (at == std::string::npos) continue;
    const std::string rest = name.substr(at + 5);
    const size_t dot = rest.find('.');
    if (dot == std::string::npos || dot == 0) continue;
    const std::string pid_text = rest.substr(0, dot);
    if (pid_text.find_first_not_of("0123456789") != std::string::npos ||
        rest.substr(dot + 1).find_first_not_of("0123456789") != std::string::npos ||
        pid_text.size() > 9) {
      continue;
    }
    const pid_t pid = static_cast<pid_t>(std::stol(pid_text));
    if (pid != ::getpid() && ::kill(pid, 0) != 0 && errno == ESRCH) fs::remove(it->path(), ec);
  }
}

// A name no other writer in this or another process uses at the same time.
fs::path TemporaryPathFor(const fs::path& path) {
  static std::atomic<unsigned> counter{0};
  fs::path temporary = path;
  temporary += ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter.fetch_add(1));
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
                 "cannot create folder " + parent.string() + ": " + error.message());
  }
}

}  // namespace

void WriteFileAtomically(const fs::path& path, std::string_view content) {
  CreateParentFolders(path);
  InstallCleanupOnce();
  RemoveStaleTemporaries(path);
  const fs::path temporary = TemporaryPathFor(path);
  const int slot = Register(temporary);
  struct Unregistered {
    int slot;
    ~Unregistered() { Unregister(slot); }
  } unregistered{slot};
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    ThrowIoError(path.string(), 0, "", "cannot create: " + ErrnoText(errno));
  }
  const bool written = WriteAll(fd, content) && ::fsync(fd) == 0;
  const int write_errno = errno;
  const bool closed = ::close(fd) == 0;
  if (!written || !closed) {
    ::unlink(temporary.c_str());
    ThrowIoError(path.string(), 0, "", "cannot write: " + ErrnoText(written ? errno : write_errno));
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
