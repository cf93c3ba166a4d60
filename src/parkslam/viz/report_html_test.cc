#include "parkslam/viz/report_html.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

namespace parkslam::viz {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

TEST(ReportHtmlTest, Base64MatchesRfc4648) {
  EXPECT_EQ(Base64(""), "");
  EXPECT_EQ(Base64("f"), "Zg==");
  EXPECT_EQ(Base64("fo"), "Zm8=");
  EXPECT_EQ(Base64("foo"), "Zm9v");
  EXPECT_EQ(Base64("foobar"), "Zm9vYmFy");
  EXPECT_EQ(Base64(std::string("\xff\x00\x10", 3)), "/wAQ");
}

TEST(ReportHtmlTest, FlattensMetricsLeaves) {
  const nlohmann::json metrics = {
      {"map", {{"slots_matched", 140}, {"slot_corner_rmse_m", 0.02812}}},
      {"detector", "classical"},
      {"band_95", {1.5, 4.5}},
      {"per_run", {{{"a", 1}}, {{"a", 2}}}}};
  const auto flat = FlattenMetrics(metrics);
  const std::vector<std::pair<std::string, std::string>> expected = {
      {"band_95", "[1.5000, 4.5000]"},
      {"detector", "classical"},
      {"map.slot_corner_rmse_m", "0.0281"},
      {"map.slots_matched", "140"}};
  EXPECT_EQ(flat, expected);
}

TEST(ReportHtmlTest, FiguresCarryBothValuesAndWhetherTheyAgree) {
  ReportData data;
  data.title = "run <1>";
  data.figures.push_back(
      {"localization.ate_rmse_m", "localization RMSE", 0.0213, 0.0213, "m", 1.0, 3});
  data.figures.push_back({"map.slots_matched", "slots matched", 139, 140, "", 1.0, 0});
  const std::string html = RenderReportHtml(data);
  EXPECT_THAT(html, HasSubstr("<title>run &lt;1&gt;</title>"));
  EXPECT_THAT(html, HasSubstr("class=\"num agree\" data-metric=\"localization.ate_rmse_m\" "
                              "data-value=\"0.021299999999999999\""));
  EXPECT_THAT(html, HasSubstr("class=\"num disagree\" data-metric=\"map.slots_matched\" "
                              "data-value=\"139\" data-recorded=\"140\""));
  // A figure the run did not record is shown without a comparison.
  data.figures.push_back({"map.tags_matched", "tags mapped", 9, std::nan(""), "", 1.0, 0});
  const std::string unrecorded = RenderReportHtml(data);
  EXPECT_THAT(unrecorded, HasSubstr("<th>tags mapped</th><td class=\"num\">9</td>"));
  EXPECT_THAT(unrecorded, Not(HasSubstr("data-metric=\"map.tags_matched\"")));
  data.figures.push_back({"", "nameless", 1, 1, "", 1.0, 0});
  EXPECT_THROW(RenderReportHtml(data), std::invalid_argument);
}

TEST(ReportHtmlTest, SelfContainedAndScriptSafe) {
  ReportData data;
  data.title = "t";
  data.scene["map"]["slots"] = nlohmann::json::array({{{"id", "</script><b>"}}});
  data.pictures.push_back({"best", std::string("\xff\xd8\xff", 3)});
  const std::string html = RenderReportHtml(data);
  // The data cannot close its script element; nothing is fetched.
  EXPECT_THAT(html, Not(HasSubstr("\"</script>")));
  EXPECT_THAT(html, HasSubstr("<\\/script><b>"));
  EXPECT_THAT(html, Not(HasSubstr("src=\"http")));
  EXPECT_THAT(html, Not(HasSubstr("href=\"http")));
  EXPECT_THAT(html, Not(HasSubstr("@import")));
  EXPECT_THAT(html, Not(HasSubstr("<link")));
  EXPECT_THAT(html, HasSubstr("src=\"data:image/jpeg;base64,/9j/\""));
  // The page's script is inside.
  EXPECT_THAT(html, HasSubstr("function selfTest()"));
}

}  // namespace
}  // namespace parkslam::viz
