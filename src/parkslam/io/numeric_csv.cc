#include "parkslam/io/numeric_csv.h"

#include <algorithm>
#include <cmath>

#include "parkslam/io/atomic_file.h"
#include "parkslam/io/io_error.h"
#include "parkslam/io/text_util.h"

namespace parkslam::io {

int NumericTable::Column(std::string_view name) const {
  const auto it = std::find(columns.begin(), columns.end(), name);
  return it == columns.end() ? -1 : static_cast<int>(it - columns.begin());
}

void WriteNumericCsv(const std::filesystem::path& path, const NumericTable& table) {
  std::string out;
  for (size_t c = 0; c < table.columns.size(); ++c) {
    const std::string& name = table.columns[c];
    if (name.empty() || name.find_first_of(",\n\r") != std::string::npos) {
      ThrowIoError(path.string(), 0, "columns",
                   "column name " + text::Quoted(name) + " is empty or holds a comma");
    }
    if (c > 0) out += ',';
    out += name;
  }
  out += '\n';
  for (size_t r = 0; r < table.rows.size(); ++r) {
    const std::vector<double>& row = table.rows[r];
    if (row.size() != table.columns.size()) {
      ThrowIoError(path.string(), static_cast<int>(r + 2), "",
                   "row of " + std::to_string(row.size()) + " values for " +
                       std::to_string(table.columns.size()) + " columns");
    }
    for (size_t c = 0; c < row.size(); ++c) {
      if (c > 0) out += ',';
      text::AppendDouble(&out, row[c]);
    }
    out += '\n';
  }
  WriteFileAtomically(path, out);
}

NumericTable ParseNumericCsv(std::string_view content, const std::string& source_name,
                             const std::vector<std::string>& required, bool allow_nan) {
  NumericTable table;
  text::LineCursor lines(content);
  std::string_view line;
  if (!lines.Next(&line)) ThrowIoError(source_name, 0, "", "empty file (expected a header line)");
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    table.columns.emplace_back(text::Trim(line.substr(start, comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  for (const std::string& name : required) {
    if (table.Column(name) < 0) ThrowIoError(source_name, 1, name, "missing column");
  }
  const size_t n = table.columns.size();
  std::vector<std::string_view> fields(n + 1);
  while (lines.Next(&line)) {
    if (text::Trim(line).empty()) continue;
    const size_t count = text::Split(line, ',', fields.data(), fields.size());
    if (count != n) {
      ThrowIoError(source_name, lines.line_number(), "",
                   std::to_string(count) + " fields for " + std::to_string(n) + " columns");
    }
    std::vector<double> row(n);
    for (size_t c = 0; c < n; ++c) {
      const std::string_view field = text::Trim(fields[c]);
      const std::optional<double> value = text::ParseDouble(field);
      if (!value) {
        ThrowIoError(source_name, lines.line_number(), table.columns[c],
                     "not a number " + text::Quoted(field));
      }
      if (std::isinf(*value) || (std::isnan(*value) && !allow_nan)) {
        ThrowIoError(source_name, lines.line_number(), table.columns[c], "not a finite number");
      }
      row[c] = *value;
    }
    table.rows.push_back(std::move(row));
  }
  return table;
}

NumericTable ReadNumericCsv(const std::filesystem::path& path,
                            const std::vector<std::string>& required, bool allow_nan) {
  return ParseNumericCsv(ReadTextFile(path), path.string(), required, allow_nan);
}

}  // namespace parkslam::io
