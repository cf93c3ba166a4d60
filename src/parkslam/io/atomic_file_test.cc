#include "parkslam/io/atomic_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <thread>

#include "parkslam/io/io_error.h"
#include "parkslam/io/test_util.h"

namespace parkslam::io {
namespace {

using ::testing::HasSubstr;
using testing::TempDir;

TEST(AtomicFileTest, WritesAndReadsBackCreatingParentFolders) {
  const TempDir dir;
  const std::filesystem::path file = dir / "a/b/c.txt";
  WriteFileAtomically(file, "line 1\nline 2\n");
  EXPECT_EQ(ReadTextFile(file), "line 1\nline 2\n");
}

TEST(AtomicFileTest, ReplacesAnExistingFileAndLeavesNoTemporaryFile) {
  const TempDir dir;
  const std::filesystem::path file = dir / "f.txt";
  WriteFileAtomically(file, "old content that is longer");
  WriteFileAtomically(file, "new");
  EXPECT_EQ(ReadTextFile(file), "new");
  int entries = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    ++entries;
  }
  EXPECT_EQ(entries, 1);
}

std::vector<std::string> Names(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    names.push_back(entry.path().filename());
  std::sort(names.begin(), names.end());
  return names;
}

// A temporary left by a process that no longer runs (SIGKILL) is removed by
// the next write into its folder; one of a running process is not.
TEST(AtomicFileTest, StaleTemporariesOfDeadProcessesAreRemoved) {
  const TempDir dir;
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ::waitpid(child, nullptr, 0);  // its pid now names no process
  const std::string dead = "map.json.tmp." + std::to_string(child) + ".7";
  const std::string alive = "map.json.tmp." + std::to_string(::getppid()) + ".2";
  std::ofstream(dir / dead) << "half a map";
  std::ofstream(dir / alive) << "being written";
  std::ofstream(dir / "notes.tmp.txt") << "not ours";
  WriteFileAtomically(dir / "other.json", "{}");
  EXPECT_EQ(Names(dir.path()), (std::vector<std::string>{alive, "notes.tmp.txt", "other.json"}));
}

// SIGTERM in the middle of a write removes the temporary before the
// process ends; the target is never created.
TEST(AtomicFileTest, ASignalDuringAWriteLeavesNoTemporary) {
  const TempDir dir;
  const pid_t child = ::fork();
  if (child == 0) {
    const std::string big(256u << 20, 'x');  // long enough to be caught writing
    WriteFileAtomically(dir / "big.bin", big);
    ::_exit(0);
  }
  bool seen = false;
  const auto start = std::chrono::steady_clock::now();
  while (!seen && std::chrono::steady_clock::now() - start < std::chrono::seconds(20)) {
    for (const std::string& name : Names(dir.path()))
      seen |= name.find(".tmp.") != std::string::npos;
    if (!seen) std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  ::kill(child, SIGTERM);
  int status = 0;
  ::waitpid(child, &status, 0);
  if (!seen || !WIFSIGNALED(status))
    GTEST_SKIP() << "the write ended before it could be interrupted";
  EXPECT_EQ(WTERMSIG(status), SIGTERM);
  EXPECT_TRUE(Names(dir.path()).empty()) << Names(dir.path()).front();
}

TEST(AtomicFileTest, KeepsBinaryContentWithZeroBytes) {
  const TempDir dir;
  const std::string content("a\0b\r\n", 5);
  WriteFileAtomically(dir / "bin", content);
  EXPECT_EQ(ReadTextFile(dir / "bin"), content);
}

TEST(AtomicFileTest, ReadingAMissingFileNamesIt) {
  const TempDir dir;
  try {
    ReadTextFile(dir / "nope.txt");
    FAIL() << "no error";
  } catch (const IoError& e) {
    EXPECT_THAT(e.what(), HasSubstr("nope.txt"));
    EXPECT_THAT(e.what(), HasSubstr("No such file"));
  }
}

TEST(AtomicFileTest, ReadingAFolderFails) {
  const TempDir dir;
  EXPECT_THROW(ReadTextFile(dir.path()), IoError);
}

TEST(AtomicFileTest, WritingIntoAFileAsFolderFails) {
  const TempDir dir;
  const std::filesystem::path file = dir.Write("plain", "x");
  EXPECT_THROW(WriteFileAtomically(file / "inside.txt", "y"), IoError);
}

}  // namespace
}  // namespace parkslam::io
