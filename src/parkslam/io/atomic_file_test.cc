#include "parkslam/io/atomic_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
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
// the next write into its folder; one of a running process is not, and
// neither is a file that merely looks like a temporary.
TEST(AtomicFileTest, StaleTemporariesOfDeadProcessesAreRemoved) {
  const TempDir dir;
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ::waitpid(child, nullptr, 0);  // its pid now names no process
  const std::string dead = TemporaryPathOf("map.json", child, 12345, 7).string();
  const std::string alive =
      TemporaryPathOf("map.json", ::getppid(), 0, 2).string();  // start unknown: kept
  std::ofstream(dir / dead) << "half a map";
  std::ofstream(dir / alive) << "being written";
  // A user's files with names of the old form or a check that does not match.
  const std::string lookalike = "precious.tmp." + std::to_string(child) + ".1";
  std::string forged = dead;
  forged.back() = forged.back() == '0' ? '1' : '0';
  std::ofstream(dir / lookalike) << "keep";
  std::ofstream(dir / forged) << "keep";
  std::ofstream(dir / "notes.tmp.txt") << "not ours";
  WriteFileAtomically(dir / "other.json", "{}");
  std::vector<std::string> expected{alive, forged, lookalike, "notes.tmp.txt", "other.json"};
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(Names(dir.path()), expected);
}

// A temporary whose pid now names another process (started at another
// time) is stale too; one with this process's own start is not.
TEST(AtomicFileTest, AReusedPidDoesNotKeepAStaleTemporary) {
  const TempDir dir;
  const unsigned long long start = ThisProcessStartTicks();
  if (start == 0) GTEST_SKIP() << "no /proc/self/stat here";
  const std::string reused = TemporaryPathOf("a.json", ::getppid(), start + 1, 0).string();
  std::ofstream(dir / reused) << "old";
  WriteFileAtomically(dir / "b.json", "{}");
  EXPECT_EQ(Names(dir.path()), (std::vector<std::string>{"b.json"}));
}

// A device, FIFO or folder where the output should go is never replaced.
TEST(AtomicFileTest, RefusesToReplaceWhatIsNotAPlainFile) {
  const TempDir dir;
  const std::filesystem::path fifo = dir / "pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  EXPECT_THROW(WriteFileAtomically(fifo, "x"), IoError);
  EXPECT_TRUE(std::filesystem::is_fifo(fifo));
  std::filesystem::create_directory(dir / "folder");
  EXPECT_THROW(WriteFileAtomically(dir / "folder", "x"), IoError);
  try {
    WriteFileAtomically("/dev/null", "x");
    ADD_FAILURE() << "replaced /dev/null";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("not a plain file"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(std::filesystem::is_character_file("/dev/null"));
  EXPECT_EQ(Names(dir.path()), (std::vector<std::string>{"folder", "pipe"}));
}

// A streamed temporary becomes the target on Commit(), and vanishes
// without it.
TEST(AtomicFileTest, ATemporaryFileIsRenamedOnlyOnCommit) {
  const TempDir dir;
  {
    TemporaryFile temporary(dir / "lost.bag");
    std::ofstream(temporary.path()) << "half";
  }
  EXPECT_TRUE(Names(dir.path()).empty());
  {
    TemporaryFile temporary(dir / "kept.bag");
    std::ofstream(temporary.path()) << "whole";
    temporary.Commit();
  }
  EXPECT_EQ(Names(dir.path()), (std::vector<std::string>{"kept.bag"}));
  EXPECT_EQ(ReadTextFile(dir / "kept.bag"), "whole");
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
