#include "parkslam/io/numeric_csv.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "parkslam/io/io_error.h"

namespace parkslam::io {
namespace {

using ::testing::HasSubstr;

std::string CsvErrorOf(std::string_view text, bool allow_nan = false) {
  try {
    ParseNumericCsv(text, "log.csv", {"t_s", "x_m"}, allow_nan);
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

TEST(NumericCsvTest, RoundTripsExactly) {
  NumericTable table;
  table.columns = {"t_s", "x_m", "gap"};
  table.rows = {{0.1, 1.0 / 3.0, std::nan("")}, {1e-9, -2.5e7, 4.0}};
  const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                     ("numeric_csv_" + std::to_string(::getpid()) + ".csv");
  WriteNumericCsv(path, table);
  const NumericTable back = ReadNumericCsv(path, {"t_s", "gap"}, true);
  std::filesystem::remove(path);
  ASSERT_EQ(back.columns, table.columns);
  ASSERT_EQ(back.rows.size(), 2u);
  EXPECT_EQ(back.rows[0][1], 1.0 / 3.0);
  EXPECT_TRUE(std::isnan(back.rows[0][2]));
  EXPECT_EQ(back.rows[1][1], -2.5e7);
  EXPECT_EQ(back.Column("gap"), 2);
  EXPECT_EQ(back.Column("none"), -1);
}

TEST(NumericCsvTest, BadTablesNameTheFileLineAndColumn) {
  EXPECT_THAT(CsvErrorOf(""), HasSubstr("log.csv: empty file"));
  EXPECT_THAT(CsvErrorOf("t_s,y_m\n1,2\n"), HasSubstr("log.csv:1: x_m: missing column"));
  EXPECT_THAT(CsvErrorOf("t_s,x_m\n1,2\n3\n"), HasSubstr("log.csv:3: 1 fields for 2 columns"));
  EXPECT_THAT(CsvErrorOf("t_s,x_m\n1,abc\n"), HasSubstr("log.csv:2: x_m: not a number 'abc'"));
  EXPECT_THAT(CsvErrorOf("t_s,x_m\n1,nan\n"), HasSubstr("log.csv:2: x_m: not a finite number"));
  EXPECT_THAT(CsvErrorOf("t_s,x_m\n1,inf\n", true),
              HasSubstr("log.csv:2: x_m: not a finite number"));
  EXPECT_EQ(CsvErrorOf("t_s,x_m\n1,nan\n", true), "");
}

TEST(NumericCsvTest, RowsOfTheWrongLengthAreNotWritten) {
  NumericTable table;
  table.columns = {"a", "b"};
  table.rows = {{1.0}};
  EXPECT_THROW(WriteNumericCsv(std::filesystem::temp_directory_path() / "never_written.csv", table),
               IoError);
  EXPECT_FALSE(
      std::filesystem::exists(std::filesystem::temp_directory_path() / "never_written.csv"));
}

}  // namespace
}  // namespace parkslam::io
