#ifndef PARKSLAM_IO_TEST_UTIL_H_
#define PARKSLAM_IO_TEST_UTIL_H_

// Helpers of the io tests.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>

#include "parkslam/io/atomic_file.h"
#include "parkslam/io/io_error.h"

namespace parkslam::io::testing {

// The message of the IoError that f throws; "" when it throws none.
template <typename F>
std::string ErrorOf(F f) {
  try {
    f();
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

// A fresh folder under the system's temporary folder, named after the
// running test and the process, removed at the end of the test.
class TempDir {
 public:
  TempDir() {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("parkslam_io_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" +
             std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

  // Writes `content` to `name` inside the folder and returns its path.
  std::filesystem::path Write(const std::string& name, const std::string& content) const {
    const std::filesystem::path file = path_ / name;
    WriteFileAtomically(file, content);
    return file;
  }

 private:
  std::filesystem::path path_;
};

}  // namespace parkslam::io::testing

#endif  // PARKSLAM_IO_TEST_UTIL_H_
