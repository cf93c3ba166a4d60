#include "parkslam/viz/report_html.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "parkslam/viz/report_page_js.h"
#include "parkslam/viz/svg.h"  // generated from report_page.js by CMake

namespace parkslam::viz {
namespace {

constexpr const char* kStyle = R"css(
body { font: 14px/1.4 sans-serif; margin: 0 auto; max-width: 1400px; padding: 0 16px; color: #222; }
h1 { font-size: 22px; } h2 { font-size: 17px; margin-top: 28px; border-bottom: 1px solid #ddd; }
table { border-collapse: collapse; } td, th { padding: 2px 10px; border-bottom: 1px solid #eee; text-align: left; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
.figures td.agree::after { content: " \2713"; color: #2a9d2a; }
.figures td.disagree { color: #d62728; font-weight: bold; }
.figures td.disagree::after { content: " \2260 metrics.json"; }
#map { height: 640px; border: 1px solid #ccc; background: #fff; }
#map-legend label { margin-right: 14px; white-space: nowrap; }
.swatch { display: inline-block; width: 14px; height: 4px; vertical-align: middle; }
.plot { display: block; } .plot-legend { font-size: 12px; margin: 0 0 8px 60px; }
.pictures { display: flex; flex-wrap: wrap; gap: 12px; }
.pictures figure { margin: 0; width: 420px; } .pictures img { width: 420px; }
code { background: #f4f4f4; padding: 1px 4px; }
#selftest-result { display: none; }
)css";

std::string Fixed(double value, int decimals) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

std::string Exact(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

// The JSON as a <script> body: "</" may not appear in it.
std::string ScriptSafe(const std::string& json) {
  std::string out;
  out.reserve(json.size());
  for (size_t i = 0; i < json.size(); ++i) {
    if (json[i] == '<' && i + 1 < json.size() && json[i + 1] == '/') {
      out += "<\\/";
      ++i;
    } else {
      out += json[i];
    }
  }
  return out;
}

void FlattenInto(const nlohmann::json& j, const std::string& prefix,
                 std::vector<std::pair<std::string, std::string>>* out) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      FlattenInto(it.value(), prefix.empty() ? it.key() : prefix + "." + it.key(), out);
    }
    return;
  }
  if (j.is_array()) {
    if (j.size() > 8) return;
    std::string text = "[";
    for (size_t k = 0; k < j.size(); ++k) {
      if (!j[k].is_primitive()) return;
      if (k > 0) text += ", ";
      text += j[k].is_number_float() ? Fixed(j[k].get<double>(), 4) : j[k].dump();
    }
    out->emplace_back(prefix, text + "]");
    return;
  }
  if (j.is_string()) {
    out->emplace_back(prefix, j.get<std::string>());
  } else if (j.is_number_float()) {
    const double v = j.get<double>();
    out->emplace_back(prefix,
                      std::abs(v) >= 1000 || v == std::floor(v) ? Fixed(v, 1) : Fixed(v, 4));
  } else {
    out->emplace_back(prefix, j.dump());
  }
}

}  // namespace

std::string Base64(std::string_view bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i < bytes.size()) {
    const bool two = i + 1 < bytes.size();
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (two ? static_cast<unsigned char>(bytes[i + 1]) << 8 : 0u);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += two ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::vector<std::pair<std::string, std::string>> FlattenMetrics(const nlohmann::json& metrics) {
  std::vector<std::pair<std::string, std::string>> out;
  FlattenInto(metrics, "", &out);
  return out;
}

namespace {

// The figures computed from the run's files, each checked against
// metrics.json where the run recorded it.
void AppendFigures(const ReportData& data, std::string* out) {
  std::string& h = *out;
  if (!data.figures.empty()) {
    h += "<h2>Figures</h2>\n<p>Each figure is computed from the run's files and, where the run "
         "recorded it, compared with <code>metrics.json</code> (&#x2713;: they agree).</p>\n"
         "<table class=\"figures\">\n";
    for (const ReportFigure& f : data.figures) {
      const bool recorded = std::isfinite(f.recorded);
      const double tolerance = 1e-9 * std::max(1.0, std::abs(f.recorded));
      const bool agrees = recorded && std::abs(f.value - f.recorded) <= tolerance;
      h += "<tr><th>";
      h += XmlEscape(f.label);
      if (recorded) {
        h += "</th><td class=\"num ";
        h += agrees ? "agree" : "disagree";
        h += "\" data-metric=\"";
        h += XmlEscape(f.key);
        h += "\" data-value=\"";
        h += Exact(f.value);
        h += "\" data-recorded=\"";
        h += Exact(f.recorded);
        h += "\">";
      } else {
        h += "</th><td class=\"num\">";
      }
      h += Fixed(f.value * f.scale, f.decimals);
      if (!f.unit.empty()) {
        h += ' ';
        h += XmlEscape(f.unit);
      }
      h += "</td><td><code>";
      h += XmlEscape(f.key);
      h += "</code></td></tr>\n";
    }
    h += "</table>\n";
  }
}

// Headings, captions and the places the page's script draws into, for
// the parts the scene holds.
void AppendPlotPlaces(const nlohmann::json& scene, std::string* out) {
  std::string& h = *out;
  if (scene.contains("map") || scene.contains("trajectories")) {
    h += "<h2>Map</h2>\n<p>Slots filled by their corner error (green 0 cm, red 10 cm or more), "
         "outlined grey where the truth has one; <span style=\"color:#d62728\">red dashed: missed; "
         "&#x2717;: wrong ID</span>; <span style=\"color:#e07b00\">orange: temporary ID</span>; "
         "pink: spurious; purple: duplicate. Corners: dots where a camera saw them (coloured by "
         "their error), hollow rings where they were only guessed. Black squares: true tags; cyan: "
         "mapped tags. Drag to "
         "pan, wheel to zoom, click near the drive to pick a time. <button id=\"map-reset\">reset "
         "view</button></p>\n<div id=\"map-legend\"></div>\n<div id=\"map\"></div>\n";
  }
  if (scene.contains("localization")) {
    h += "<h2>Localization over time</h2>\n<p>Click a plot to mark the car's place on the map "
         "(green ring: true pose; blue: estimate).</p>\n"
         "<div id=\"plot-error\"></div>\n<div id=\"plot-state\"></div>\n<div "
         "id=\"plot-seen\"></div>\n"
         "<div id=\"plot-nees\"></div>\n<p>NEES of the localizer's pose against the truth at each "
         "tracked frame; green: the 95 % band of a consistent filter (&chi;&sup2;, 3 degrees of "
         "freedom).</p>\n";
  }
  if (scene.contains("ekf")) {
    h += "<h2>Dead-reckoning EKF consistency</h2>\n<div id=\"plot-anees\"></div>\n<p>Average NEES "
         "over repeated simulated drives; green: its 95 % band.</p>\n";
  }
  if (scene.contains("follow")) {
    h += "<h2>Autonomous runs along the recorded trace</h2>\n<div id=\"plot-lateral\"></div>\n<p>"
         "Signed lateral offset of each run's true path from the trace (left positive); the runs' "
         "paths are on the map.</p>\n";
  }
}

// The perception table and the sample pictures, inline.
void AppendPerception(const ReportData& data, std::string* out) {
  std::string& h = *out;
  if (!data.pictures.empty() || !data.perception_table.empty()) {
    h += "<h2>Perception</h2>\n";
    if (!data.perception_table.empty()) {
      h += "<table>\n";
      for (size_t r = 0; r < data.perception_table.size(); ++r) {
        h += "<tr>";
        for (const std::string& cell : data.perception_table[r]) {
          h += r == 0 ? "<th>" + XmlEscape(cell) + "</th>"
                      : "<td class=\"num\">" + XmlEscape(cell) + "</td>";
        }
        h += "</tr>\n";
      }
      h += "</table>\n";
    }
    h += "<p>Green circles: true marking points; red: detected, with their direction; orange: "
         "entrance lines of the detected slots.</p>\n<div class=\"pictures\">\n";
    for (const ReportPicture& p : data.pictures) {
      h += "<figure><img alt=\"" + XmlEscape(p.caption) + "\" src=\"data:image/jpeg;base64," +
           Base64(p.jpeg) + "\"><figcaption>" + XmlEscape(p.caption) + "</figcaption></figure>\n";
    }
    h += "</div>\n";
  }
}

// Every figure of metrics.json, flattened.
void AppendMetrics(const ReportData& data, std::string* out) {
  std::string& h = *out;
  if (!data.metrics.empty()) {
    h += "<h2>metrics.json</h2>\n<table>\n";
    for (const auto& [key, value] : data.metrics) {
      h += "<tr><td><code>" + XmlEscape(key) + "</code></td><td class=\"num\">" + XmlEscape(value) +
           "</td></tr>\n";
    }
    h += "</table>\n";
  }
}

}  // namespace

std::string RenderReportHtml(const ReportData& data) {
  for (const ReportFigure& f : data.figures) {
    if (f.key.empty())
      throw std::invalid_argument("RenderReportHtml: a figure without a metrics key");
  }
  const nlohmann::json& scene = data.scene;
  std::string h;
  h.reserve(1 << 20);
  h += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>";
  h += XmlEscape(data.title);
  h += "</title>\n<style>";
  h += kStyle;
  h += "</style></head><body>\n<h1>" + XmlEscape(data.title) + "</h1>\n";
  h += "<p>Made by <code>" + XmlEscape(data.command) + "</code>, parkslam " +
       XmlEscape(data.version) + ".</p>\n";

  AppendFigures(data, &h);
  AppendPlotPlaces(scene, &h);
  AppendPerception(data, &h);
  AppendMetrics(data, &h);
  h += "<pre id=\"selftest-result\"></pre>\n<script type=\"application/json\" id=\"report-data\">";
  h += ScriptSafe(scene.dump());
  h += "</script>\n<script>";
  h += kReportPageJs;
  h += "</script>\n</body></html>\n";
  return h;
}

}  // namespace parkslam::viz
