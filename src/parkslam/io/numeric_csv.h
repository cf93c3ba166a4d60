#ifndef PARKSLAM_IO_NUMERIC_CSV_H_
#define PARKSLAM_IO_NUMERIC_CSV_H_

// Tables of numbers as CSV with a header line: the per-frame logs a run
// leaves for its report (localization.csv, ekf_nees.csv,
// follow/lateral.csv; docs/report.md). Numbers are written so that they
// read back exactly; NaN is written "nan" and means "no value" (a station a
// run did not cover).

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace parkslam::io {

struct NumericTable {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;  // each as long as columns

  // The index of a column, or -1.
  int Column(std::string_view name) const;
};

// Writes atomically. Throws IoError when a row's length differs from the
// header's or a column name is empty or holds a comma.
void WriteNumericCsv(const std::filesystem::path& path, const NumericTable& table);

// Reads a table written by WriteNumericCsv. Every column of `required` must
// be in the header. Throws IoError naming the file, line and column for a
// missing column, a row of the wrong length, a field that is not a number,
// or an infinity; NaN ("nan") only where allow_nan.
NumericTable ParseNumericCsv(std::string_view text, const std::string& source_name,
                             const std::vector<std::string>& required, bool allow_nan);
NumericTable ReadNumericCsv(const std::filesystem::path& path,
                            const std::vector<std::string>& required, bool allow_nan = false);

}  // namespace parkslam::io

#endif  // PARKSLAM_IO_NUMERIC_CSV_H_
