// `parkslam report` as a user meets it: a run folder made by `demo`, its
// page's figures against metrics.json, and the page in a real browser
// (headless Chromium): it loads without an error, the map and every plot
// are drawn, and clicks link the plots and the map. The browser part is
// skipped, with a message, where /usr/bin/chromium is absent.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

namespace {

namespace fs = std::filesystem;

std::string Slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

int Shell(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class ReportTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::temp_directory_path() /
                        ("parkslam_report_test_" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_);
    const std::string command =
        std::string(PARKSLAM_BIN) + " demo --out " + (*dir_ / "run").string() +
        " --observations --consistency-runs 5 --follow-runs 2 --perception-frames 6"
        " --world " PARKSLAM_SOURCE_DIR "/config/worlds/small.yaml > " +
        (*dir_ / "demo.log").string() + " 2>&1";
    demo_status_ = Shell(command);
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
  }
  static fs::path run() { return *dir_ / "run"; }

  static fs::path* dir_;
  static int demo_status_;
};

fs::path* ReportTest::dir_ = nullptr;
int ReportTest::demo_status_ = -1;

// Every headline figure on the page is computed again from the run's files
// and must agree with metrics.json at its key.
TEST_F(ReportTest, EveryFigureAgreesWithMetricsJson) {
  ASSERT_EQ(demo_status_, 0) << Slurp(*dir_ / "demo.log");
  const std::string html = Slurp(run() / "report.html");
  ASSERT_FALSE(html.empty());
  const nlohmann::json metrics = nlohmann::json::parse(Slurp(run() / "metrics.json"));
  const std::regex figure("data-metric=\"([a-z_0-9.]+)\" data-value=\"([^\"]+)\"");
  int figures = 0;
  for (auto it = std::sregex_iterator(html.begin(), html.end(), figure);
       it != std::sregex_iterator(); ++it) {
    const std::string key = (*it)[1];
    const double shown = std::stod((*it)[2]);
    nlohmann::json::json_pointer pointer("/" + std::regex_replace(key, std::regex("\\."), "/"));
    ASSERT_TRUE(metrics.contains(pointer)) << key;
    const double recorded = metrics[pointer].get<double>();
    EXPECT_NEAR(shown, recorded, 1e-9 * std::max(1.0, std::abs(recorded))) << key;
    ++figures;
  }
  // Map (12: 7, observed and unobserved corners' RMSE and 2-sigma shares,
  // IDs read from worn paint), localization (7: 3, and slot and tag
  // observations made and used), EKF (2), follow (1).
  EXPECT_EQ(figures, 24);
  EXPECT_EQ(html.find("num disagree"), std::string::npos);
  // The numbers of metrics.json are on the page too, with the command that made them.
  EXPECT_THAT(html,
              ::testing::HasSubstr("<code>map.slots_matched</code></td><td class=\"num\">" +
                                   std::to_string(metrics["map"]["slots_matched"].get<int>())));
  EXPECT_THAT(html, ::testing::HasSubstr(" demo --out "));
}

TEST_F(ReportTest, TheCommandWritesTheSamePageAndRefusesAnEmptyFolder) {
  ASSERT_EQ(demo_status_, 0);
  const fs::path out = *dir_ / "again.html";
  ASSERT_EQ(Shell(std::string(PARKSLAM_BIN) + " report " + run().string() + " --out " +
                  out.string() + " > /dev/null"),
            0);
  EXPECT_EQ(Slurp(out), Slurp(run() / "report.html"));
  fs::create_directories(*dir_ / "empty");
  EXPECT_NE(Shell(std::string(PARKSLAM_BIN) + " report " + (*dir_ / "empty").string() + " 2> " +
                  (*dir_ / "err.txt").string()),
            0);
  EXPECT_THAT(Slurp(*dir_ / "err.txt"), ::testing::HasSubstr("nothing to report"));
  EXPECT_FALSE(fs::exists(*dir_ / "empty" / "report.html"));
}

// Issue: "report over 1e308 positions and negative variances" drew a page
// of infinities, exit 0. A run folder whose localization.csv holds one is
// refused naming the file, the line and the column; so is a metrics.json
// whose values have the wrong type.
TEST_F(ReportTest, AbsurdRunFilesAreRefusedNamingLineAndField) {
  ASSERT_EQ(demo_status_, 0);
  const std::string log = Slurp(run() / "localization.csv");
  const std::size_t header_end = log.find('\n');
  ASSERT_NE(header_end, std::string::npos);
  const std::string header = log.substr(0, header_end);
  // Column `name` of the first row set to `value`.
  const auto edited = [&](const std::string& name, const std::string& value) {
    std::vector<std::string> columns, cells;
    std::stringstream h(header),
        row(log.substr(header_end + 1, log.find('\n', header_end + 1) - header_end - 1));
    for (std::string c; std::getline(h, c, ',');) columns.push_back(c);
    for (std::string c; std::getline(row, c, ',');) cells.push_back(c);
    std::string out = header + "\n";
    for (std::size_t i = 0; i < cells.size(); ++i) {
      out += (i > 0 ? "," : "") + (columns[i] == name ? value : cells[i]);
    }
    return out + log.substr(log.find('\n', header_end + 1));
  };
  const auto error_of = [&](const std::string& file, const std::string& text) {
    const fs::path folder = *dir_ / "absurd";
    fs::remove_all(folder);
    fs::create_directories(folder);
    std::ofstream(folder / file) << text;
    const int status = Shell(std::string(PARKSLAM_BIN) + " report " + folder.string() + " 2> " +
                             (*dir_ / "absurd.txt").string());
    EXPECT_NE(status, 0) << file;
    EXPECT_FALSE(fs::exists(folder / "report.html")) << file;
    return Slurp(*dir_ / "absurd.txt");
  };
  EXPECT_THAT(error_of("localization.csv", edited("x_m", "1e308")),
              ::testing::HasSubstr("absurd/localization.csv:2: x_m: 1e+308 is beyond the "
                                   "plausible 100000 m"));
  EXPECT_THAT(error_of("localization.csv", edited("cov_yy", "-0.5")),
              ::testing::HasSubstr("absurd/localization.csv:2: cov_yy: -0.5 is outside the "
                                   "plausible range [0, 1e+10] m^2"));
  EXPECT_THAT(error_of("metrics.json", "{\"perception\": {\"images\": \"six\"}}"),
              ::testing::HasSubstr("absurd/metrics.json: perception.images: expected a number"));
  EXPECT_THAT(error_of("metrics.json", "{\"dataset\": 7}"),
              ::testing::HasSubstr("absurd/metrics.json: dataset: expected text"));
  // An independent probe: a flag of 2.5, trace-following offsets of 1e308 and
  // stations out of order.
  EXPECT_THAT(error_of("localization.csv", edited("relocalized", "2.5")),
              ::testing::HasSubstr("absurd/localization.csv:2: relocalized: 2.5 is outside the "
                                   "plausible range [0, 1]"));
  EXPECT_THAT(error_of("lateral.csv", "s_m,run_00_m\n0,0.01\n0.5,1e308\n"),
              ::testing::HasSubstr("absurd/lateral.csv:3: run_00_m: 1e+308 is beyond the "
                                   "plausible 100000 m"));
  EXPECT_THAT(error_of("lateral.csv", "s_m,run_00_m\n0.5,0.01\n0,0.02\n"),
              ::testing::HasSubstr("absurd/lateral.csv:3: s_m: not increasing"));
}

// Pixels of a colour (within a tolerance) inside a rectangle of the screenshot.
int CountColour(const cv::Mat& image, const std::vector<double>& rect, cv::Vec3b bgr,
                int tolerance = 40) {
  const cv::Rect r(static_cast<int>(rect[0]), static_cast<int>(rect[1]), static_cast<int>(rect[2]),
                   static_cast<int>(rect[3]));
  const cv::Rect clipped = r & cv::Rect(0, 0, image.cols, image.rows);
  int count = 0;
  for (int y = clipped.y; y < clipped.y + clipped.height; ++y) {
    for (int x = clipped.x; x < clipped.x + clipped.width; ++x) {
      const cv::Vec3b p = image.at<cv::Vec3b>(y, x);
      count +=
          std::abs(p[0] - bgr[0]) + std::abs(p[1] - bgr[1]) + std::abs(p[2] - bgr[2]) <= tolerance;
    }
  }
  return count;
}

TEST_F(ReportTest, OpensInHeadlessChromiumAndLinksPlotsAndMap) {
  const char* chromium = "/usr/bin/chromium";
  if (!fs::exists(chromium)) {
    GTEST_SKIP() << "no /usr/bin/chromium: the browser check of the report is skipped "
                    "(apt-get install chromium, or scripts/install_deps.sh)";
  }
  ASSERT_EQ(demo_status_, 0);
  const std::string url = "file://" + fs::absolute(run() / "report.html").string() + "#selftest";
  const std::string flags = std::string(chromium) +
                            " --headless=new --no-sandbox --disable-gpu --hide-scrollbars "
                            "--window-size=1400,4200 --user-data-dir=" +
                            (*dir_ / "profile").string() +
                            " --enable-logging=stderr --v=0 --virtual-time-budget=5000 ";
  const fs::path dom = *dir_ / "dom.html", log = *dir_ / "chromium.log", shot = *dir_ / "shot.png";
  ASSERT_EQ(Shell(flags + "--dump-dom '" + url + "' > " + dom.string() + " 2> " + log.string()), 0)
      << Slurp(log);
  // No console error, no uncaught exception.
  const std::string console = Slurp(log);
  EXPECT_EQ(console.find("Uncaught"), std::string::npos) << console;
  EXPECT_EQ(console.find(":ERROR:CONSOLE"), std::string::npos) << console;
  const std::string page = Slurp(dom);
  std::smatch match;
  ASSERT_TRUE(
      std::regex_search(page, match, std::regex("<pre id=\"selftest-result\">([^<]*)</pre>")))
      << "no self-test result in the page";
  const nlohmann::json result = nlohmann::json::parse(match[1].str());
  EXPECT_TRUE(result["errors"].empty()) << result.dump();
  for (const char* check :
       {"map_drawn", "plots_drawn", "plot_click_moves_marker", "map_click_moves_cursor"}) {
    EXPECT_EQ(result["checks"].value(check, false), true) << check << ": " << result.dump();
  }
  EXPECT_TRUE(result.value("ok", false));

  // A screenshot: the map and each plot hold pixels of their colours.
  ASSERT_EQ(Shell(flags + "--screenshot=" + shot.string() + " '" + url + "' > /dev/null 2>&1"), 0);
  const cv::Mat image = cv::imread(shot.string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty());
  const nlohmann::json& rects = result["rects"];
  const auto rect = [&](const char* id) { return rects.at(id).get<std::vector<double>>(); };
  // Map: slots filled green (small errors, at 55 % over white) and the truth in green.
  EXPECT_GT(CountColour(image, rect("map"), cv::Vec3b(118, 200, 118), 60), 500);
  EXPECT_GT(CountColour(image, rect("plot-error"), cv::Vec3b(0xb4, 0x77, 0x1f)), 50);    // #1f77b4
  EXPECT_GT(CountColour(image, rect("plot-state"), cv::Vec3b(0x2c, 0xa0, 0x2c)), 50);    // #2ca02c
  EXPECT_GT(CountColour(image, rect("plot-seen"), cv::Vec3b(0xbd, 0x67, 0x94)), 20);     // #9467bd
  EXPECT_GT(CountColour(image, rect("plot-nees"), cv::Vec3b(0x28, 0x27, 0xd6)), 50);     // #d62728
  EXPECT_GT(CountColour(image, rect("plot-anees"), cv::Vec3b(0x4b, 0x56, 0x8c)), 50);    // #8c564b
  EXPECT_GT(CountColour(image, rect("plot-lateral"), cv::Vec3b(0x28, 0x27, 0xd6)), 50);  // #d62728
}

}  // namespace
