#include "parkslam/io/output_guard.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "parkslam/io/io_error.h"

namespace parkslam::io {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class OutputGuardTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("output_guard_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "ds" / "sensors");
    std::ofstream(dir_ / "ds" / "dataset.yaml") << "x";
    std::ofstream(dir_ / "map.json") << "{}";
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string ErrorOf(const fs::path& out, const std::vector<NamedPath>& inputs,
                      bool folder = false) {
    try {
      CheckOutputsSpareInputs({{out, "--out", folder}}, inputs);
    } catch (const IoError& e) {
      return e.what();
    }
    return "";
  }

  fs::path dir_;
};

TEST_F(OutputGuardTest, RefusesAnInputFileByAnyName) {
  const std::vector<NamedPath> inputs{{dir_ / "map.json", "--map"}};
  EXPECT_THAT(ErrorOf(dir_ / "map.json", inputs), HasSubstr("is the input --map"));
  EXPECT_THAT(ErrorOf(dir_ / "ds" / ".." / "map.json", inputs), HasSubstr("is the input --map"));
  // Through a folder that does not exist yet (a writer would make it).
  EXPECT_THAT(ErrorOf(dir_ / "new" / ".." / "map.json", inputs), HasSubstr("is the input --map"));
  fs::create_hard_link(dir_ / "map.json", dir_ / "link.json");
  EXPECT_THAT(ErrorOf(dir_ / "link.json", inputs), HasSubstr("is the input --map"));
  fs::create_symlink(dir_ / "map.json", dir_ / "sym.json");
  EXPECT_THAT(ErrorOf(dir_ / "sym.json", inputs), HasSubstr("is the input --map"));
}

TEST_F(OutputGuardTest, RefusesOutputsInsideAnInputFolder) {
  const std::vector<NamedPath> inputs{{dir_ / "ds", "DIR"}};
  EXPECT_THAT(ErrorOf(dir_ / "ds" / "dataset.yaml", inputs),
              HasSubstr("lies inside the input DIR"));
  EXPECT_THAT(ErrorOf(dir_ / "ds" / "sensors" / "new.csv", inputs),
              HasSubstr("lies inside the input DIR"));
  EXPECT_THAT(ErrorOf(dir_ / "ds", inputs), HasSubstr("the input DIR"));
  // A sibling whose name starts the same is not inside.
  EXPECT_EQ(ErrorOf(dir_ / "ds2" / "x.tum", inputs), "");
  EXPECT_EQ(ErrorOf(dir_ / "out.tum", inputs), "");
}

TEST_F(OutputGuardTest, RefusesAnOutputFolderHoldingAnInput) {
  EXPECT_THAT(ErrorOf(dir_, {{dir_ / "map.json", "--map"}}),
              HasSubstr("is a folder that holds the input --map"));
  // Missing inputs are the reader's business; empty paths are not given.
  EXPECT_EQ(ErrorOf(dir_ / "out.json", {{dir_ / "absent.json", "--map"}, {"", "--trace"}}), "");
}

// `map --out a.json --trajectory-out a.json`: the second would replace the
// first, under any spelling.
TEST_F(OutputGuardTest, RefusesTwoOutputsOfOneFile) {
  const auto error_of = [](const std::vector<NamedPath>& outputs) -> std::string {
    try {
      CheckOutputsSpareInputs(outputs, {});
    } catch (const IoError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_THAT(error_of({{dir_ / "a.json", "--out"}, {dir_ / "a.json", "--trajectory-out"}}),
              HasSubstr("--trajectory-out " + (dir_ / "a.json").string() + ": is also --out"));
  EXPECT_THAT(error_of({{dir_ / "a.json", "--out"}, {dir_ / "ds" / ".." / "a.json", "--log"}}),
              HasSubstr("is also --out"));
  EXPECT_EQ(error_of({{dir_ / "map.json", "--out"}, {dir_ / "sym.json", "--log"}}), "");
  fs::create_symlink(dir_ / "map.json", dir_ / "sym.json");
  EXPECT_THAT(error_of({{dir_ / "map.json", "--out"}, {dir_ / "sym.json", "--log"}}),
              HasSubstr("is also --out"));
  EXPECT_EQ(error_of({{dir_ / "a.json", "--out"}, {dir_ / "b.json", "--log"}, {"", "--x"}}), "");
}

// `--out /dev/null` as root would replace the device with a file.
TEST_F(OutputGuardTest, RefusesAnOutputWhereADeviceOrFifoIs) {
  EXPECT_THAT(ErrorOf("/dev/null", {}), HasSubstr("is not a plain file or a folder"));
  ASSERT_EQ(::mkfifo((dir_ / "pipe").c_str(), 0644), 0);
  EXPECT_THAT(ErrorOf(dir_ / "pipe", {}), HasSubstr("a device, FIFO or socket"));
  EXPECT_EQ(ErrorOf(dir_ / "map.json", {}), "");
  EXPECT_EQ(ErrorOf(dir_ / "ds", {}, /*folder=*/true), "");
}

// An independent probe: `map --out m.json --trajectory-out o.x/` wrote
// m.json and then failed, leaving it and an empty folder o.x. A file
// output that cannot be written is refused before anything is.
TEST_F(OutputGuardTest, RefusesAFileOutputThatCannotBeWritten) {
  EXPECT_THAT(ErrorOf(dir_.string() + "/o.x/", {}),
              HasSubstr("o.x/: names a folder (it ends in /); this output is a file"));
  EXPECT_THAT(ErrorOf(dir_ / "ds", {}), HasSubstr("ds: is a folder, not a file"));
  EXPECT_THAT(ErrorOf(dir_ / "map.json" / "o.x", {}),
              HasSubstr("cannot be made: " + (dir_ / "map.json").string() + " is a file"));
  EXPECT_THAT(ErrorOf(dir_ / "map.json" / "deeper" / "o.x", {}), HasSubstr("is a file"));
  // Folders that do not exist yet are made by the writer; a folder output
  // may end in / and may exist.
  EXPECT_EQ(ErrorOf(dir_ / "new" / "sub" / "o.tum", {}), "");
  EXPECT_EQ(ErrorOf(dir_.string() + "/ds2/", {}, /*folder=*/true), "");
  EXPECT_EQ(ErrorOf(dir_ / "ds", {}, /*folder=*/true), "");
}

}  // namespace
}  // namespace parkslam::io
