// parkslam report: one self-contained HTML page of a run folder
// (docs/report.md). Reads what the folder holds, computes the headline
// figures again from the run's own files, and lays them beside
// metrics.json's.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "parkslam/common/angles.h"
#include "parkslam/common/plausible_ranges.h"
#include "parkslam/eval/map_metrics.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/dataset.h"
#include "parkslam/io/image_header.h"
#include "parkslam/io/io_error.h"
#include "parkslam/io/json_util.h"
#include "parkslam/io/map_json.h"
#include "parkslam/io/numeric_csv.h"
#include "parkslam/io/output_guard.h"
#include "parkslam/io/text_util.h"
#include "parkslam/io/tum.h"
#include "parkslam/viz/report_html.h"
#include "steps.h"

namespace parkslam::app {

namespace fs = std::filesystem;

namespace report_command {

// The chi-square 95 % band of a 3-dimensional NEES sample (x, y, yaw).
constexpr double kNees3Lower = 0.2158;
constexpr double kNees3Upper = 9.3484;

std::string g_command_line;

// Every JSON input is read one way (io/json_util.h): its errors name the
// file, the line and column and the field, in the project's words.
nlohmann::json ReadJson(const fs::path& path) {
  return io::json_util::ParseJson(io::ReadTextFile(path, io::kMaxJsonBytes), path.string(), 0);
}

// The value at `key` of the object `j` of metrics.json, `fallback` where
// the key is absent; `where` names the file and the object's key
// ("run/metrics.json: perception.slots", or the file alone for the top). Another type is an error
// that says so, where nlohmann's own get<>() would throw its type_error text.
template <typename T>
T ValueOf(const nlohmann::json& j, const char* key, T fallback, const std::string& where) {
  if (!j.is_object()) throw io::IoError(where + ": expected a JSON object");
  if (!j.contains(key)) return fallback;
  const nlohmann::json& v = j[key];
  // "run/metrics.json: dataset", "run/metrics.json: perception.images".
  const std::string field = where + (where.find(": ") == std::string::npos ? ": " : ".") + key;
  if constexpr (std::is_same_v<T, std::string>) {
    if (!v.is_string()) throw io::IoError(field + ": expected text");
    return v.get<std::string>();
  } else {
    if (!v.is_number()) throw io::IoError(field + ": expected a number");
    const double number = v.get<double>();
    if constexpr (std::is_integral_v<T>) {
      if (!(number >= 0 && number <= 1e9)) {
        throw io::IoError(field + ": expected a count in [0, 1e9]");
      }
    }
    return static_cast<T>(number);
  }
}

// metrics.json's number at a dotted key, or NaN.
double Recorded(const nlohmann::json& metrics, const std::string& key) {
  std::string path = "/" + key;
  std::replace(path.begin(), path.end(), '.', '/');
  const nlohmann::json::json_pointer pointer(path);
  return metrics.contains(pointer) && metrics[pointer].is_number() ? metrics[pointer].get<double>()
                                                                   : std::nan("");
}

// Trajectories on the map are thinned to about one point every 0.25 m.
nlohmann::json Polyline(const Trajectory& trajectory) {
  nlohmann::json xy = nlohmann::json::array();
  Eigen::Vector2d last(1e300, 1e300);
  for (size_t i = 0; i < trajectory.size(); ++i) {
    const Eigen::Vector2d p = trajectory[i].T_map_vehicle.translation();
    if ((p - last).norm() < 0.25 && i + 1 != trajectory.size()) continue;
    xy.push_back({std::round(p.x() * 1000) / 1000, std::round(p.y() * 1000) / 1000});
    last = p;
  }
  return xy;
}

nlohmann::json Corners(const MapSlot& slot, const SE2& T) {
  nlohmann::json c = nlohmann::json::array();
  for (const Eigen::Vector2d& p : slot.corners_map) {
    const Eigen::Vector2d q = T * p;
    c.push_back({q.x(), q.y()});
  }
  return c;
}

const char* VerdictName(eval::SlotVerdict v) {
  switch (v) {
    case eval::SlotVerdict::kMatched:
      return "matched";
    case eval::SlotVerdict::kSpurious:
      return "spurious";
    case eval::SlotVerdict::kDuplicate:
      return "duplicate";
    case eval::SlotVerdict::kNotCounted:
      return "not_counted";
  }
  return "spurious";
}

struct Loaded {
  viz::ReportData data;
  nlohmann::json metrics;
  std::string prefix;  // "" for a demo folder's metrics, "trace_following." where nested
};

void AddFigure(Loaded* r, const std::string& key, const std::string& label, double value,
               const std::string& unit, double scale, int decimals) {
  // NaN where the run did not record it (map/localize folders).
  r->data.figures.push_back({key, label, value, Recorded(r->metrics, key), unit, scale, decimals});
}

// The map of the folder: --map, DIR/map.json, or the map a follow
// folder's metrics name.
fs::path MapPathOf(const fs::path& dir, const ReportInputs& inputs, const Loaded& r) {
  fs::path map_path = inputs.map.empty() ? dir / "map.json" : inputs.map;
  // A follow folder names the map it ran on.
  if (inputs.map.empty() && !fs::exists(map_path) && r.metrics.contains("map") &&
      r.metrics["map"].is_string()) {
    map_path = r.metrics["map"].get<std::string>();
  }
  return map_path;
}

// The map's slots as they are, where no truth judges them.
nlohmann::json UnjudgedSlots(const SemanticMap& map) {
  nlohmann::json slots = nlohmann::json::array();
  for (const MapSlot& s : map.slots) {
    slots.push_back(
        {{"c", Corners(s, SE2())},
         {"id", s.id},
         {"temporary", s.temporary},
         {"verdict", "not_counted"},
         {"err_m", 0.0},
         {"observed",
          {s.corner_observed[0], s.corner_observed[1], s.corner_observed[2], s.corner_observed[3]}},
         {"id_right", true}});
  }
  return slots;
}

// The map drawn over the truth, in the truth's frame, with each slot's verdict.
nlohmann::json JudgedMap(const SemanticMap& map, const SemanticMap& truth,
                         const eval::MapMetrics& m) {
  nlohmann::json truth_slots = nlohmann::json::array(), slots = nlohmann::json::array();
  for (const MapSlot& s : truth.slots)
    truth_slots.push_back({{"c", Corners(s, SE2())}, {"id", s.id}});
  for (size_t i = 0; i < map.slots.size(); ++i) {
    const eval::MapSlotVerdict& v = m.map_slots[i];
    const auto& observed = map.slots[i].corner_observed;
    slots.push_back({{"c", Corners(map.slots[i], m.T_truth_map)},
                     {"id", map.slots[i].id},
                     {"temporary", map.slots[i].temporary},
                     {"verdict", VerdictName(v.verdict)},
                     {"err_m", v.corner_rms_m},
                     {"corner_err_m", v.corner_error_m},
                     {"observed", {observed[0], observed[1], observed[2], observed[3]}},
                     {"id_right", v.id_right},
                     {"id_worn_read", v.id_worn_read}});
  }
  nlohmann::json truth_tags = nlohmann::json::array(), tags = nlohmann::json::array();
  for (const MapTag& t : truth.tags)
    truth_tags.push_back({{"p", {t.p_map.x(), t.p_map.y()}}, {"id", t.tag_id}});
  for (const MapTag& t : map.tags) {
    const Eigen::Vector2d p = m.T_truth_map * t.p_map;
    tags.push_back({{"p", {p.x(), p.y()}}, {"id", t.tag_id}});
  }
  return {{"truth_slots", truth_slots},
          {"slots", slots},
          {"missed", m.missed_truth_slots},
          {"truth_tags", truth_tags},
          {"tags", tags}};
}

// The mapping drive: its truth, and dead reckoning and the optimized
// keyframes where the folder has them.
void AddMappingDrive(const fs::path& dir, const io::Dataset& dataset, const eval::MapMetrics& m,
                     nlohmann::json* scene) {
  (*scene)["trajectories"].push_back({{"name", "mapping drive: truth"},
                                      {"colour", "#2a9d2a"},
                                      {"xy", Polyline(dataset.groundtruth_trajectory)}});
  if (fs::exists(dir / "odometry.tum")) {
    (*scene)["trajectories"].push_back({{"name", "mapping drive: dead reckoning"},
                                        {"colour", "#d62728"},
                                        {"width", 1.0},
                                        {"hidden", true},
                                        {"xy", Polyline(io::ReadTum(dir / "odometry.tum"))}});
  }
  if (fs::exists(dir / "trajectory.tum")) {
    (*scene)["trajectories"].push_back(
        {{"name", "mapping drive: optimized keyframes"},
         {"colour", "#1f77b4"},
         {"width", 1.0},
         {"hidden", true},
         {"xy", Polyline(Transformed(m.T_truth_map, io::ReadTum(dir / "trajectory.tum")))}});
  }
}

void AddMapFigures(const eval::MapMetrics& m, Loaded* r) {
  const std::string p = "map.";
  AddFigure(r, p + "slots_matched", "slots matched", m.slots_matched,
            "of " + std::to_string(m.slots_true), 1, 0);
  AddFigure(r, p + "slots_missed", "slots missed", m.slots_missed, "", 1, 0);
  AddFigure(r, p + "slots_spurious", "spurious slots", m.slots_spurious, "", 1, 0);
  AddFigure(r, p + "slots_duplicate", "duplicate slots", m.slots_duplicate, "", 1, 0);
  AddFigure(r, p + "slot_corner_rmse_m", "slot corner RMSE", m.slot_corner_rmse_m, "cm", 100, 1);
  AddFigure(r, p + "observed_corners.rmse_m", "observed corner RMSE", m.observed_corners.rmse_m,
            "cm", 100, 1);
  AddFigure(r, p + "unobserved_corners.rmse_m", "unobserved (guessed) corner RMSE",
            m.unobserved_corners.rmse_m, "cm", 100, 1);
  AddFigure(r, p + "observed_corners.within_2sigma", "observed corners inside 2 sigma",
            m.observed_corners.within_2sigma, "%", 100, 1);
  AddFigure(r, p + "unobserved_corners.within_2sigma", "unobserved corners inside 2 sigma",
            m.unobserved_corners.within_2sigma, "%", 100, 1);
  AddFigure(r, p + "id_accuracy", "IDs right", m.id_accuracy, "%", 100, 1);
  AddFigure(r, p + "ids_worn_read", "IDs read right from worn paint", m.ids_worn_read, "", 1, 0);
  AddFigure(r, p + "tags_matched", "tags mapped", m.tags_matched,
            "of " + std::to_string(m.tags_true), 1, 0);
}

void AddMap(const fs::path& dir, const ReportInputs& inputs, Loaded* r) {
  const fs::path map_path = MapPathOf(dir, inputs, *r);
  if (!fs::exists(map_path)) return;
  const SemanticMap map = io::ReadMap(map_path);
  nlohmann::json& scene = r->data.scene;
  const fs::path dataset_dir = inputs.dataset.empty() ? dir / "dataset" : inputs.dataset;
  const bool has_truth = fs::exists(dataset_dir / "groundtruth" / "map.json");
  if (!has_truth) {
    scene["map"]["slots"] = UnjudgedSlots(map);
    return;
  }
  const io::Dataset dataset = io::ReadDataset(dataset_dir);
  const SemanticMap& truth = *dataset.groundtruth_map;
  eval::MapMetricsOptions options;
  options.truth_slot_mask = PassedSlots(dataset, truth.slots.size(), 3);
  const eval::MapMetrics m = eval::EvaluateMap(map, truth, options);
  scene["map"] = JudgedMap(map, truth, m);
  AddMappingDrive(dir, dataset, m, &scene);
  AddMapFigures(m, r);
}

// Sums of squared errors over the frames where the localizer tracked.
struct TrackedErrors {
  double sum_sq = 0.0, sum_yaw_sq = 0.0;
  int tracked = 0;
  // Landmark observations over the log: made and used, by class.
  int slots_seen = 0, slots_used = 0, tags_seen = 0, tags_used = 0;
  // NEES of the tracked frames: their sum, count and how many lie inside
  // the per-frame 95 % band.
  double nees_sum = 0.0;
  int nees_frames = 0, nees_inside = 0;
};

// One row of localization.csv within the plausible ranges
// (common/plausible_ranges.h): positions in the map frame, angles, and a
// covariance's variances (non-negative, a position's at most the square of
// the map's extent), counts and the state small non-negative integers. A
// 1e308 position or a negative variance drew a page of infinities.
void CheckLocalizationRow(const io::NumericTable& log, std::size_t k, const fs::path& path) {
  const std::vector<double>& row = log.rows[k];
  const auto fail = [&](const std::string& field, const std::string& what) {
    throw io::IoError(path.string() + ":" + std::to_string(k + 2) + ": " + field + ": " + what);
  };
  const auto bounded = [&](const char* name, double max_abs, const char* unit) {
    const double v = row[static_cast<size_t>(log.Column(name))];
    if (std::abs(v) > max_abs) fail(name, io::text::BeyondPlausible(v, max_abs, unit));
  };
  const auto in_range = [&](const char* name, double min, double max, const char* unit) {
    const double v = row[static_cast<size_t>(log.Column(name))];
    if (v < min || v > max) fail(name, io::text::OutsidePlausible(v, min, max, unit));
  };
  constexpr double kMaxVariance_m2 = kMaxCoordinate_m * kMaxCoordinate_m;
  for (const char* name : {"x_m", "y_m", "true_x_m", "true_y_m"}) {
    bounded(name, kMaxCoordinate_m, "m");
  }
  for (const char* name : {"yaw_rad", "true_yaw_rad"}) bounded(name, kMaxAngle_rad, "rad");
  for (const char* name : {"cov_xx", "cov_yy"}) in_range(name, 0.0, kMaxVariance_m2, "m^2");
  in_range("cov_yawyaw", 0.0, kMaxAngle_rad * kMaxAngle_rad, "rad^2");
  bounded("cov_xy", kMaxVariance_m2, "m^2");
  for (const char* name : {"cov_xyaw", "cov_yyaw"}) {
    bounded(name, kMaxCoordinate_m * kMaxAngle_rad, "m rad");
  }
  in_range("state", 0, 2, "");
  for (const char* name : {"slots_seen", "slots_used", "tags_seen", "tags_used"}) {
    in_range(name, 0, 1e6, "");
  }
  in_range("relocalized", 0, 1, "");
}

// The log's series for the plots (rounded), from localization.csv.
nlohmann::json LocalizationSeries(const io::NumericTable& log, const fs::path& path,
                                  TrackedErrors* errors) {
  const auto col = [&](const char* name) { return static_cast<size_t>(log.Column(name)); };
  nlohmann::json l;
  std::vector<std::string> names = {"t",     "x",    "y",     "yaw",         "tx",
                                    "ty",    "tyaw", "err_m", "yaw_err_deg", "state",
                                    "slots", "tags", "reloc", "nees"};
  for (const std::string& n : names) l[n] = nlohmann::json::array();
  double& sum_sq = errors->sum_sq;
  double& sum_yaw_sq = errors->sum_yaw_sq;
  int& tracked = errors->tracked;
  for (size_t k = 0; k < log.rows.size(); ++k) {
    const std::vector<double>& row = log.rows[k];
    CheckLocalizationRow(log, k, path);
    if (k > 0 && !(row[col("t_s")] > log.rows[k - 1][col("t_s")])) {
      throw io::IoError(path.string() + ":" + std::to_string(k + 2) + ": t_s: not increasing");
    }
    const Eigen::Vector3d e(row[col("x_m")] - row[col("true_x_m")],
                            row[col("y_m")] - row[col("true_y_m")],
                            NormalizeAngle(row[col("yaw_rad")] - row[col("true_yaw_rad")]));
    Eigen::Matrix3d P;
    P << row[col("cov_xx")], row[col("cov_xy")], row[col("cov_xyaw")], row[col("cov_xy")],
        row[col("cov_yy")], row[col("cov_yyaw")], row[col("cov_xyaw")], row[col("cov_yyaw")],
        row[col("cov_yawyaw")];
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(P);
    const double nees =
        ldlt.info() == Eigen::Success && ldlt.isPositive() ? e.dot(ldlt.solve(e)) : std::nan("");
    const int state = static_cast<int>(row[col("state")]);
    const double err_m = e.head<2>().norm();
    if (state == 1) {
      ++tracked;
      sum_sq += err_m * err_m;
      sum_yaw_sq += e.z() * e.z();
      if (std::isfinite(nees)) {
        ++errors->nees_frames;
        errors->nees_sum += nees;
        errors->nees_inside += nees >= kNees3Lower && nees <= kNees3Upper;
      }
    }
    const auto r3 = [](double v) { return std::round(v * 1e4) / 1e4; };
    l["t"].push_back(row[col("t_s")]);
    l["x"].push_back(r3(row[col("x_m")]));
    l["y"].push_back(r3(row[col("y_m")]));
    l["yaw"].push_back(r3(row[col("yaw_rad")]));
    l["tx"].push_back(row[col("true_x_m")]);
    l["ty"].push_back(row[col("true_y_m")]);
    l["tyaw"].push_back(r3(row[col("true_yaw_rad")]));
    l["err_m"].push_back(std::round(err_m * 1e5) / 1e5);
    l["yaw_err_deg"].push_back(std::round(e.z() * 180 / M_PI * 1e4) / 1e4);
    l["state"].push_back(state);
    l["slots"].push_back(static_cast<int>(row[col("slots_used")]));
    l["tags"].push_back(static_cast<int>(row[col("tags_used")]));
    errors->slots_seen += static_cast<int>(row[col("slots_seen")]);
    errors->slots_used += static_cast<int>(row[col("slots_used")]);
    errors->tags_seen += static_cast<int>(row[col("tags_seen")]);
    errors->tags_used += static_cast<int>(row[col("tags_used")]);
    l["reloc"].push_back(row[col("relocalized")] != 0.0);
    if (std::isfinite(nees)) {
      l["nees"].push_back(std::round(nees * 1e4) / 1e4);
    } else {
      l["nees"].push_back(nullptr);
    }
  }
  return l;
}

// The second drive's truth and tracked estimate, from the log.
void AddSecondDrive(const io::NumericTable& log, Loaded* r) {
  const auto col = [&](const char* name) { return static_cast<size_t>(log.Column(name)); };
  Trajectory truth, estimate;
  for (const std::vector<double>& row : log.rows) {
    const TimeNs t = FromSeconds(row[col("t_s")]);
    if (!truth.empty() && t <= truth.back().t_ns) continue;
    truth.push_back({t, SE2(row[col("true_x_m")], row[col("true_y_m")], row[col("true_yaw_rad")])});
    if (static_cast<int>(row[col("state")]) == 1) {
      estimate.push_back({t, SE2(row[col("x_m")], row[col("y_m")], row[col("yaw_rad")])});
    }
  }
  r->data.scene["trajectories"].push_back({{"name", "second drive: truth"},
                                           {"colour", "#006400"},
                                           {"hidden", true},
                                           {"xy", Polyline(truth)}});
  r->data.scene["trajectories"].push_back(
      {{"name", "second drive: localized"}, {"colour", "#1f77b4"}, {"xy", Polyline(estimate)}});
}

void AddLocalization(const fs::path& dir, Loaded* r) {
  const fs::path path = dir / "localization.csv";
  if (!fs::exists(path)) return;
  const io::NumericTable log = io::ReadNumericCsv(
      path, {"t_s", "x_m", "y_m", "yaw_rad", "state", "slots_seen", "slots_used", "tags_seen",
             "tags_used", "relocalized", "cov_xx", "cov_xy", "cov_xyaw", "cov_yy", "cov_yyaw",
             "cov_yawyaw", "true_x_m", "true_y_m", "true_yaw_rad"});
  TrackedErrors errors;
  r->data.scene["localization"] = LocalizationSeries(log, path, &errors);
  r->data.scene["nees_band"] = {kNees3Lower, kNees3Upper};
  AddSecondDrive(log, r);
  const int tracked = errors.tracked;
  if (tracked > 0) {
    AddFigure(r, "localization.frames_tracked", "frames tracked", tracked, "", 1, 0);
    AddFigure(r, "localization.ate_rmse_m", "localization RMSE", std::sqrt(errors.sum_sq / tracked),
              "m", 1, 3);
    AddFigure(r, "localization.yaw_rmse_deg", "localization yaw RMSE",
              std::sqrt(errors.sum_yaw_sq / tracked) * 180 / M_PI, "deg", 1, 3);
    // Each landmark class's use, so that a class lost between the front
    // end and the localizer shows.
    const std::string p = "localization.landmarks.";
    AddFigure(r, p + "slots.observed", "slot observations", errors.slots_seen, "", 1, 0);
    AddFigure(r, p + "slots.used", "slot observations used", errors.slots_used, "", 1, 0);
    AddFigure(r, p + "tags.observed", "tag observations", errors.tags_seen, "", 1, 0);
    AddFigure(r, p + "tags.used", "tag observations used", errors.tags_used, "", 1, 0);
  }
  if (errors.nees_frames > 0) {
    AddFigure(r, "localization.nees.mean", "localization NEES, mean (ideal 3)",
              errors.nees_sum / errors.nees_frames, "", 1, 2);
    AddFigure(r, "localization.nees.share_inside_frame_band",
              "localization NEES inside the per-frame 95 % band",
              static_cast<double>(errors.nees_inside) / errors.nees_frames, "%", 100, 1);
  }
}

void AddEkf(const fs::path& dir, Loaded* r) {
  const fs::path path = dir / "ekf_nees.csv";
  if (!fs::exists(path)) return;
  const io::NumericTable t = io::ReadNumericCsv(path, {"t_s", "anees"});
  nlohmann::json ekf = {{"t", nlohmann::json::array()}, {"anees", nlohmann::json::array()}};
  double sum = 0.0;
  const auto t_col = static_cast<size_t>(t.Column("t_s"));
  const auto anees_col = static_cast<size_t>(t.Column("anees"));
  for (size_t k = 0; k < t.rows.size(); ++k) {
    const std::vector<double>& row = t.rows[k];
    const std::string line = path.string() + ":" + std::to_string(k + 2) + ": ";
    if (k > 0 && !(row[t_col] > t.rows[k - 1][t_col]))
      throw io::IoError(line + "t_s: not increasing");
    // A NEES is a squared distance: never negative.
    if (row[anees_col] < 0.0) throw io::IoError(line + "anees: must not be negative");
    ekf["t"].push_back(row[t_col]);
    ekf["anees"].push_back(row[anees_col]);
    sum += row[anees_col];
  }
  const nlohmann::json& c = r->metrics.contains("odometry_consistency")
                                ? r->metrics["odometry_consistency"]
                                : nlohmann::json::object();
  if (c.contains("band_95") && c["band_95"].is_array() && c["band_95"].size() == 2 &&
      c["band_95"][0].is_number() && c["band_95"][1].is_number()) {
    const double band_lo = c["band_95"][0].get<double>(), band_hi = c["band_95"][1].get<double>();
    ekf["band"] = {band_lo, band_hi};
    int inside = 0;
    for (const std::vector<double>& row : t.rows) {
      inside += row[anees_col] >= band_lo && row[anees_col] <= band_hi;
    }
    if (!t.rows.empty()) {
      AddFigure(r, "odometry_consistency.share_inside_band", "EKF ANEES inside its 95 % band",
                static_cast<double>(inside) / static_cast<double>(t.rows.size()), "%", 100, 1);
    }
  }
  ekf["runs"] = ValueOf(c, "runs", 0, (dir / "metrics.json").string() + ": odometry_consistency");
  if (!t.rows.empty()) {
    AddFigure(r, "odometry_consistency.mean_anees", "EKF average NEES (ideal 3)",
              sum / static_cast<double>(t.rows.size()), "", 1, 2);
  }
  r->data.scene["ekf"] = ekf;
}

void AddFollow(const fs::path& follow_dir, const std::string& key_prefix, Loaded* r) {
  const fs::path path = follow_dir / "lateral.csv";
  if (!fs::exists(path)) return;
  const io::NumericTable t = io::ReadNumericCsv(path, {"s_m"}, true);
  for (size_t k = 0; k < t.rows.size(); ++k) {
    const int line = static_cast<int>(k) + 2;
    if (k > 0 && !(t.rows[k][0] > t.rows[k - 1][0])) {
      io::ThrowIoError(path.string(), line, "s_m", "not increasing (stations run along the trace)");
    }
    for (size_t c = 0; c < t.columns.size(); ++c) {
      if (std::abs(t.rows[k][c]) > kMaxCoordinate_m) {
        io::ThrowIoError(path.string(), line, t.columns[c],
                         io::text::BeyondPlausible(t.rows[k][c], kMaxCoordinate_m, "m"));
      }
    }
  }
  nlohmann::json follow = {{"s", nlohmann::json::array()}, {"runs", nlohmann::json::array()}};
  for (const std::vector<double>& row : t.rows) follow["s"].push_back(row[0]);
  for (size_t c = 1; c < t.columns.size(); ++c) {
    nlohmann::json offsets = nlohmann::json::array();
    for (const std::vector<double>& row : t.rows) {
      if (std::isnan(row[c])) {
        offsets.push_back(nullptr);
      } else {
        offsets.push_back(std::round(row[c] * 1e5) / 1e5);
      }
    }
    std::string name = t.columns[c];
    if (name.size() > 2 && name.compare(name.size() - 2, 2, "_m") == 0)
      name.resize(name.size() - 2);
    const char* colour = kRunColours[(c - 1) % kRunColours.size()];
    follow["runs"].push_back({{"name", name}, {"colour", colour}, {"offsets", offsets}});
    const fs::path run = follow_dir / (name + ".tum");
    if (fs::exists(run)) {
      r->data.scene["trajectories"].push_back({{"name", "autonomous " + name},
                                               {"colour", colour},
                                               {"width", 1.0},
                                               {"xy", Polyline(io::ReadTum(run))}});
    }
  }
  // A follow folder's trace (the demo draws its mapping drive, the same).
  if (key_prefix.empty() && fs::exists(follow_dir / "trace.tum")) {
    r->data.scene["trajectories"].push_back(
        {{"name", "the trace"},
         {"colour", "#2a9d2a"},
         {"xy", Polyline(io::ReadTum(follow_dir / "trace.tum"))}});
  }
  // The repeated-trace standard deviation (eval/trace_metrics.h), again.
  double variance_sum = 0.0;
  int stations = 0;
  for (const std::vector<double>& row : t.rows) {
    double sum = 0.0;
    int n = 0;
    for (size_t c = 1; c < row.size(); ++c) {
      if (!std::isnan(row[c])) {
        sum += row[c];
        ++n;
      }
    }
    if (n < 2) continue;
    const double mean = sum / n;
    double squares = 0.0;
    for (size_t c = 1; c < row.size(); ++c) {
      if (!std::isnan(row[c])) squares += (row[c] - mean) * (row[c] - mean);
    }
    variance_sum += squares / n;
    ++stations;
  }
  if (stations > 0) {
    AddFigure(r, key_prefix + "repeat_std_m", "repeated-trace standard deviation",
              std::sqrt(variance_sum / stations), "m", 1, 4);
  }
  r->data.scene["follow"] = follow;
}

void AddPerception(const fs::path& dir, Loaded* r) {
  if (!r->metrics.contains("perception")) return;
  const nlohmann::json& p = r->metrics["perception"];
  const std::string where = (dir / "metrics.json").string() + ": perception";
  const auto row = [&](const char* what, const char* key) {
    if (!p.is_object() || !p.contains(key)) return;
    const nlohmann::json& c = p[key];
    const std::string at = where + "." + key;
    char precision[32], recall[32];
    std::snprintf(precision, sizeof precision, "%.1f %%", 100 * ValueOf(c, "precision", 0.0, at));
    std::snprintf(recall, sizeof recall, "%.1f %%", 100 * ValueOf(c, "recall", 0.0, at));
    r->data.perception_table.push_back({what, precision, recall,
                                        std::to_string(ValueOf(c, "true_positives", 0, at)),
                                        std::to_string(ValueOf(c, "false_positives", 0, at)),
                                        std::to_string(ValueOf(c, "false_negatives", 0, at))});
  };
  r->data.perception_table.push_back(
      {"over " + std::to_string(ValueOf(p, "images", 0, where)) + " top views", "precision",
       "recall", "true", "false", "missed"});
  row("marking points", "marking_points");
  row("slots", "slots");
  if (!p.contains("pictures")) return;
  if (!p["pictures"].is_array()) throw io::IoError(where + ".pictures: expected an array");
  for (std::size_t i = 0; i < p["pictures"].size(); ++i) {
    const nlohmann::json& picture = p["pictures"][i];
    const std::string at = where + ".pictures[" + std::to_string(i) + "]";
    const fs::path file = dir / ValueOf(picture, "file", std::string(), at);
    if (!fs::is_regular_file(file)) continue;
    io::CheckImageSize(file);  // a cut or absurdly large picture is refused, named
    char caption[400];
    std::snprintf(caption, sizeof caption, "%s (t = %.0f s: %d slots right, %d false, %d missed)",
                  ValueOf(picture, "caption", std::string(), at).c_str(),
                  ValueOf(picture, "t_s", 0.0, at), ValueOf(picture, "slots_true_positives", 0, at),
                  ValueOf(picture, "slots_false_positives", 0, at),
                  ValueOf(picture, "slots_false_negatives", 0, at));
    r->data.pictures.push_back({caption, io::ReadTextFile(file, io::kMaxImageBytes)});
  }
}

}  // namespace report_command

void SetCommandLine(int argc, char** argv) {
  using namespace report_command;
  g_command_line.clear();
  for (int i = 0; i < argc; ++i) {
    std::string arg = i == 0 ? "parkslam" : argv[i];
    if (arg.find_first_of(" \t'\"") != std::string::npos) arg = "'" + arg + "'";
    g_command_line += (i > 0 ? " " : "") + arg;
  }
}

const std::string& CommandLine() { return report_command::g_command_line; }

void WriteReport(const fs::path& dir, const ReportInputs& inputs, const fs::path& out) {
  using namespace report_command;
  if (!fs::is_directory(dir)) throw io::IoError(dir.string() + ": not a folder");
  Loaded r;
  r.metrics = nlohmann::json::object();
  const fs::path metrics_path = dir / "metrics.json";
  if (fs::exists(metrics_path)) r.metrics = ReadJson(metrics_path);
  if (!r.metrics.is_object()) throw io::IoError(metrics_path.string() + ": expected a JSON object");
  const bool follow_folder = fs::exists(dir / "lateral.csv");
  r.data.title = follow_folder
                     ? "parkslam follow: " + dir.filename().string()
                     : "parkslam run: " + ValueOf(r.metrics, "dataset", dir.filename().string(),
                                                  metrics_path.string());
  r.data.command =
      ValueOf(r.metrics, "command", std::string("(not recorded)"), metrics_path.string());
  r.data.version = ValueOf(r.metrics, "version", std::string(kVersion), metrics_path.string());
  r.data.scene = nlohmann::json::object();
  r.data.scene["trajectories"] = nlohmann::json::array();
  AddMap(dir, inputs, &r);
  AddLocalization(dir, &r);
  AddEkf(dir, &r);
  if (follow_folder) {
    AddFollow(dir, "", &r);
  } else {
    AddFollow(dir / "follow", "trace_following.", &r);
  }
  AddPerception(dir, &r);
  r.data.metrics = viz::FlattenMetrics(r.metrics);
  if (r.data.scene["trajectories"].empty()) r.data.scene.erase("trajectories");
  if (r.data.figures.empty() && r.data.scene.empty() && r.data.metrics.empty()) {
    throw io::IoError(dir.string() +
                      ": nothing to report (no metrics.json, map.json, localization.csv "
                      "or lateral.csv)");
  }
  io::WriteFileAtomically(out, viz::RenderReportHtml(r.data));
}

void AddReportCommand(CLI::App& app) {
  using namespace report_command;
  struct Options {
    std::string dir, out, map, dataset;
  };
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "report",
      "Write one self-contained HTML page of a run folder (demo, follow, or a folder holding "
      "map.json, localization.csv and the dataset): the map with true and estimated "
      "trajectories, slots coloured by corner error, plots over time linked to the map, "
      "follow runs, perception pictures and metrics.json (docs/report.md)");
  cmd->add_option("DIR", options->dir, "Run folder")->required();
  cmd->add_option("--out", options->out, "HTML file to write (default: DIR/report.html)");
  cmd->add_option("--map", options->map, "Map JSON to draw (default: DIR/map.json)");
  cmd->add_option("--dataset", options->dataset,
                  "Dataset whose ground truth the map is judged against (default: DIR/dataset)");
  cmd->callback([options] {
    const auto start = std::chrono::steady_clock::now();
    const fs::path out =
        options->out.empty() ? fs::path(options->dir) / "report.html" : fs::path(options->out);
    // The page may go into the run folder, never over what it reads.
    std::vector<io::NamedPath> read;
    for (const char* name : {"metrics.json", "map.json", "localization.csv", "ekf_nees.csv",
                             "lateral.csv", "odometry.tum", "trajectory.tum", "trace.tum"}) {
      read.push_back({fs::path(options->dir) / name, "DIR"});
    }
    for (const char* folder : {"dataset", "follow", "perception", "second_drive"}) {
      read.push_back({fs::path(options->dir) / folder, "DIR"});
    }
    read.push_back({options->map, "--map"});
    read.push_back({options->dataset, "--dataset"});
    io::CheckOutputsSpareInputs({{out, "--out"}}, read);
    ReportInputs inputs;
    inputs.map = options->map;
    inputs.dataset = options->dataset;
    WriteReport(options->dir, inputs, out);
    std::printf("wrote %s (%.1f MB) in %.2f s\n", out.string().c_str(),
                static_cast<double>(fs::file_size(out)) / 1e6,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  });
}

}  // namespace parkslam::app
