#include "parkslam/io/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <system_error>
#include <utility>
#include <vector>

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

// When the process `pid` started, in clock ticks since boot (field 22 of
// /proc/PID/stat), or 0 where that cannot be read: with the pid, a name no
// other process of this boot can have.
unsigned long long StartTicksOf(long pid) {
  std::string stat;
  try {
    stat = ReadTextFile("/proc/" + std::to_string(pid) + "/stat");
  } catch (const IoError&) {
    return 0;
  }
  // "pid (comm) state ppid ...": the command may hold spaces and brackets.
  const size_t close = stat.rfind(')');
  if (close == std::string::npos) return 0;
  std::istringstream fields(stat.substr(close + 1));
  std::string field;
  for (int k = 3; k <= 22 && fields >> field; ++k) {
    if (k == 22) return std::strtoull(field.c_str(), nullptr, 10);
  }
  return 0;
}

// A check of the other parts of a temporary's name, so that the sweep
// below never takes a file of the user's that merely looks like one.
std::string NameCheck(const std::string& target_name, long pid, unsigned long long start,
                      unsigned serial) {
  const std::string key = "parkslam|" + target_name + "|" + std::to_string(pid) + "|" +
                          std::to_string(start) + "|" + std::to_string(serial);
  std::uint32_t hash = 2166136261u;  // FNV-1a
  for (const unsigned char c : key) hash = (hash ^ c) * 16777619u;
  char text[9];
  std::snprintf(text, sizeof(text), "%08x", hash);
  return text;
}

struct TemporaryName {
  std::string target_name;  // the file it becomes
  long pid = 0;
  unsigned long long start = 0;
};

// The parts of "<name>.tmp.<pid>.<start>.<serial>.<check>", if `name` is
// exactly that with a check that matches.
std::optional<TemporaryName> ParseTemporaryName(const std::string& name) {
  const size_t at = name.rfind(".tmp.");
  if (at == std::string::npos || at == 0) return std::nullopt;
  std::vector<std::string> parts;
  std::istringstream rest(name.substr(at + 5));
  for (std::string part; std::getline(rest, part, '.');) parts.push_back(part);
  if (parts.size() != 4) return std::nullopt;
  for (int k = 0; k < 3; ++k) {
    if (parts[k].empty() || parts[k].size() > 19 ||
        parts[k].find_first_not_of("0123456789") != std::string::npos) {
      return std::nullopt;
    }
  }
  TemporaryName parsed;
  parsed.target_name = name.substr(0, at);
  parsed.pid = std::strtol(parts[0].c_str(), nullptr, 10);
  parsed.start = std::strtoull(parts[1].c_str(), nullptr, 10);
  const unsigned long serial = std::strtoul(parts[2].c_str(), nullptr, 10);
  if (parsed.pid <= 0 || serial > std::numeric_limits<unsigned>::max() ||
      parts[3] !=
          NameCheck(parsed.target_name, parsed.pid, parsed.start, static_cast<unsigned>(serial))) {
    return std::nullopt;
  }
  return parsed;
}

// Whether the process that named a temporary has ended: its pid names no
// process, or one that started at another time (the pid was reused).
bool WriterEnded(const TemporaryName& name) {
  if (name.pid == ::getpid()) return false;
  if (::kill(static_cast<pid_t>(name.pid), 0) != 0 && errno == ESRCH) return true;
  const unsigned long long start = StartTicksOf(name.pid);
  return name.start != 0 && start != 0 && start != name.start;
}

// Temporaries left in the folder of `path` by a process that no longer
// runs (killed with SIGKILL, or a power cut). Only names this code makes,
// with a check that matches, are taken. Each folder is looked through once
// per process.
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
    const std::optional<TemporaryName> name = ParseTemporaryName(it->path().filename().string());
    if (!name || !WriterEnded(*name)) continue;
    std::error_code type_error;
    if (it->is_symlink(type_error)) continue;
    if (it->is_regular_file(type_error)) fs::remove(it->path(), type_error);
    if (it->is_directory(type_error)) fs::remove_all(it->path(), type_error);  // a staging folder
  }
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

// A file that already stands at `path` and is not a plain file (a device,
// a FIFO, a socket, a folder) is never replaced: as root, `--out /dev/null`
// would otherwise replace the device with a file.
void RefuseToReplaceSpecialFile(const fs::path& path) {
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (error || !fs::exists(status)) return;  // missing, or a dangling link
  if (fs::is_directory(status)) ThrowIoError(path.string(), 0, "", "is a folder, not a file");
  if (!fs::is_regular_file(status)) {
    ThrowIoError(path.string(), 0, "",
                 "exists and is not a plain file (a device, FIFO or socket); not replaced");
  }
}

}  // namespace

fs::path TemporaryPathOf(const fs::path& path, long pid, unsigned long long start_ticks,
                         unsigned serial) {
  const std::string target_name = path.filename().string();
  fs::path temporary = path;
  temporary += ".tmp." + std::to_string(pid) + "." + std::to_string(start_ticks) + "." +
               std::to_string(serial) + "." + NameCheck(target_name, pid, start_ticks, serial);
  return temporary;
}

unsigned long long ThisProcessStartTicks() {
  static const unsigned long long start = StartTicksOf(::getpid());
  return start;
}

TemporaryFile::TemporaryFile(fs::path target, Kind kind) : target_(std::move(target)) {
  if (kind == Kind::kFile) {
    RefuseToReplaceSpecialFile(target_);
  } else {
    std::error_code error;
    if (fs::exists(target_, error) && !fs::is_directory(target_, error)) {
      ThrowIoError(target_.string(), 0, "", "is not a folder");
    }
  }
  CreateParentFolders(target_);
  InstallCleanupOnce();
  RemoveStaleTemporaries(target_);
  // A name no other writer in this or another process uses at the same time.
  static std::atomic<unsigned> counter{0};
  temporary_ = TemporaryPathOf(target_, ::getpid(), ThisProcessStartTicks(), counter.fetch_add(1));
  slot_ = Register(temporary_);
}

TemporaryFile::~TemporaryFile() {
  if (!committed_) {
    std::error_code error;
    fs::remove_all(temporary_, error);  // a file, or a folder a writer filled
  }
  Unregister(slot_);
}

void TemporaryFile::Commit() {
  const int fd = ::open(temporary_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) ThrowIoError(target_.string(), 0, "", "cannot write: " + ErrnoText(errno));
  const bool synced = ::fsync(fd) == 0;
  const int sync_errno = errno;
  ::close(fd);
  if (!synced) ThrowIoError(target_.string(), 0, "", "cannot write: " + ErrnoText(sync_errno));
  if (::rename(temporary_.c_str(), target_.c_str()) != 0) {
    ThrowIoError(target_.string(), 0, "", "cannot replace: " + ErrnoText(errno));
  }
  committed_ = true;
}

void WriteFileAtomically(const fs::path& path, std::string_view content) {
  TemporaryFile temporary(path);
  const int fd =
      ::open(temporary.path().c_str(), O_WRONLY | O_CREAT | O_EXCL | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    ThrowIoError(path.string(), 0, "", "cannot create: " + ErrnoText(errno));
  }
  const bool written = WriteAll(fd, content);
  const int write_errno = errno;
  const bool closed = ::close(fd) == 0;
  if (!written || !closed) {
    ThrowIoError(path.string(), 0, "", "cannot write: " + ErrnoText(written ? errno : write_errno));
  }
  temporary.Commit();
}

namespace {

std::string Megabytes(std::uintmax_t bytes) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f MB", static_cast<double>(bytes) / 1e6);
  return text;
}

// The refusal of a file whose `status` is not a plain one of at most
// `max_bytes`.
void CheckStatus(const fs::path& path, const struct stat& status, std::uintmax_t max_bytes) {
  if (S_ISDIR(status.st_mode)) ThrowIoError(path.string(), 0, "", "is a folder, not a file");
  if (!S_ISREG(status.st_mode)) {
    ThrowIoError(path.string(), 0, "",
                 "is not a plain file (a FIFO, device or socket); inputs are read from plain "
                 "files only");
  }
  const auto size = static_cast<std::uintmax_t>(status.st_size);
  if (size > max_bytes) {
    ThrowIoError(path.string(), 0, "",
                 "is " + Megabytes(size) + ", more than the " + Megabytes(max_bytes) +
                     " such an input may be (docs/plausible_ranges.md, \"Input sizes\")");
  }
}

}  // namespace

std::uintmax_t CheckInputFile(const fs::path& path, std::uintmax_t max_bytes) {
  struct stat status {};
  if (::stat(path.c_str(), &status) != 0) {
    ThrowIoError(path.string(), 0, "", "cannot open: " + ErrnoText(errno));
  }
  CheckStatus(path, status, max_bytes);
  return static_cast<std::uintmax_t>(status.st_size);
}

std::string ReadTextFile(const fs::path& path, std::uintmax_t max_bytes) {
  // O_NONBLOCK: opening a FIFO would otherwise wait for a writer.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) {
    ThrowIoError(path.string(), 0, "", "cannot open: " + ErrnoText(errno));
  }
  struct Closed {
    int fd;
    ~Closed() { ::close(fd); }
  } closed{fd};
  struct stat status {};
  if (::fstat(fd, &status) != 0) {
    ThrowIoError(path.string(), 0, "", "cannot read: " + ErrnoText(errno));
  }
  CheckStatus(path, status, max_bytes);
  std::string content;
  content.reserve(static_cast<std::size_t>(status.st_size));
  char buffer[1 << 16];
  while (true) {
    const ssize_t n = ::read(fd, buffer, sizeof(buffer));
    if (n == 0) break;
    if (n < 0) {
      if (errno == EINTR || errno == EAGAIN) continue;
      ThrowIoError(path.string(), 0, "", "cannot read: " + ErrnoText(errno));
    }
    content.append(buffer, static_cast<std::size_t>(n));
    // A file that grows while read, or one of /proc that states no size.
    if (content.size() > max_bytes) {
      ThrowIoError(path.string(), 0, "",
                   "grew past the " + Megabytes(max_bytes) + " such an input may be");
    }
  }
  return content;
}

}  // namespace parkslam::io
