#ifndef PARKSLAM_VIZ_REPORT_HTML_H_
#define PARKSLAM_VIZ_REPORT_HTML_H_

// One self-contained HTML page per run (docs/report.md): the map with the
// true and estimated trajectories, slots coloured by their corner error,
// plots over time of localization error, state, landmarks seen and NEES,
// the follow runs' lateral deviation, perception pictures and every number
// of metrics.json. No network, no external scripts or fonts: the data is
// embedded as JSON, drawn as SVG by a script in the page, and the pictures
// are JPEGs inlined as base64.
//
// Clicking a plot marks the car's place at that time on the map; clicking
// the map near the localized drive moves the plots' cursor to that time.
// Opened with "#selftest" the page checks itself (map and plots drawn, a
// click on the error plot moves the map's marker, a click on the map moves
// the plots' cursor) and writes the outcome as JSON into the element
// `#selftest-result`, for a headless browser to read.

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace parkslam::viz {

// A headline figure, computed by the report from the run's files and tied
// to the metrics.json key it must agree with; the page carries both values
// (data-metric, data-value, data-recorded) so that a test can compare them.
struct ReportFigure {
  std::string key;        // "localization.ate_rmse_m"
  std::string label;      // "localization RMSE"
  double value = 0.0;     // as the report computed it
  double recorded = 0.0;  // as metrics.json has it; NaN where it does not
  std::string unit;       // shown after the value, after scaling
  double scale = 1.0;     // shown value = value * scale
  int decimals = 3;
};

struct ReportPicture {
  std::string caption;
  std::string jpeg;  // the file's bytes
};

struct ReportData {
  std::string title;
  std::string command;
  std::string version;
  std::vector<ReportFigure> figures;
  // metrics.json flattened: ("map.slots_matched", "140").
  std::vector<std::pair<std::string, std::string>> metrics;
  // What the page's script draws (docs/report.md "The page's data"): map,
  // trajectories, localization, nees, follow; any part may be absent.
  nlohmann::json scene = nlohmann::json::object();
  std::vector<ReportPicture> pictures;
  // Perception table: a header row, then rows.
  std::vector<std::vector<std::string>> perception_table;
};

// The page. Throws std::invalid_argument for a figure whose key is empty.
std::string RenderReportHtml(const ReportData& data);

// RFC 4648 base64 of `bytes`.
std::string Base64(std::string_view bytes);

// metrics.json's leaves as ("a.b.c", text) pairs in key order; arrays of
// numbers are written "[1, 2]"; larger arrays and objects in arrays are
// left out ("per_run" and the like).
std::vector<std::pair<std::string, std::string>> FlattenMetrics(const nlohmann::json& metrics);

}  // namespace parkslam::viz

#endif  // PARKSLAM_VIZ_REPORT_HTML_H_
