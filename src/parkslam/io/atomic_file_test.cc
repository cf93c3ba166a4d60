#include "parkslam/io/atomic_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

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
