#include "parkslam/options/option_ranges.h"

#include <gtest/gtest.h>

#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <string>

namespace parkslam {
namespace {

// Issue: "84 of 201 options keys take 1e308": every number of the options
// has a row, and every row bounds a number that exists.
TEST(OptionRangesTest, EveryNumberHasARowAndEveryRowANumber) {
  std::set<std::string> keys;
  for (const auto& [key, value] : NumericOptions(AlgorithmOptions{})) {
    keys.insert(key);
    const OptionRange* range = FindOptionRange(key);
    ASSERT_NE(range, nullptr) << key << " has no row in option_ranges.cc";
    EXPECT_TRUE(range->Contains(value)) << key << " = " << value << " outside " << range->Text();
  }
  // The empty list front_end.top_view.camera_priority_rad gives no number.
  keys.insert("front_end.top_view.camera_priority_rad");
  EXPECT_GT(keys.size(), 180u);
  std::set<std::string> rows;
  for (const OptionRange& row : OptionRanges()) {
    EXPECT_TRUE(rows.insert(std::string(row.key)).second) << row.key << " has two rows";
    EXPECT_TRUE(keys.count(std::string(row.key)) == 1) << row.key << " bounds no option";
    EXPECT_LT(row.min, row.max) << row.key;
    EXPECT_FALSE(row.why.empty()) << row.key;
  }
}

TEST(OptionRangesTest, BoundsAreOpenOrClosedAsWritten) {
  const OptionRange* tag = FindOptionRange("front_end.tags.tag_size_m");
  ASSERT_NE(tag, nullptr);
  EXPECT_EQ(tag->Text(), "(0, 5] m");
  EXPECT_FALSE(tag->Contains(0.0));
  EXPECT_TRUE(tag->Contains(5.0));
  EXPECT_FALSE(tag->Contains(5.0001));
  EXPECT_FALSE(tag->Contains(std::numeric_limits<double>::quiet_NaN()));
  EXPECT_FALSE(tag->Contains(std::numeric_limits<double>::infinity()));
  const OptionRange* gate = FindOptionRange("localizer.gate_probability");
  ASSERT_NE(gate, nullptr);
  EXPECT_EQ(gate->Text(), "(0.5, 1)");
  EXPECT_FALSE(gate->Contains(1.0));
  // The classical block inside the learned detector takes front_end.slots's rows.
  EXPECT_EQ(FindOptionRange("front_end.learned_slots.classical_options.min_arm_m"),
            FindOptionRange("front_end.slots.min_arm_m"));
  EXPECT_EQ(FindOptionRange("front_end.slots.no_such_key"), nullptr);
}

TEST(OptionRangesTest, TheFirstNumberOutsideIsNamedWithItsRange) {
  AlgorithmOptions options;
  options.front_end.tags.tag_size_m = 1e308;
  std::string error;
  EXPECT_FALSE(CheckOptionRanges(options, &error));
  EXPECT_EQ(error, "front_end.tags.tag_size_m: 1e+308 is outside the plausible range (0, 5] m");
  options = AlgorithmOptions{};
  options.front_end.top_view.camera_priority_rad = {0.1, 2.0};
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_EQ(error,
            "front_end.top_view.camera_priority_rad: 2 is outside the plausible range "
            "[-1.5, 1.5] rad");
  options = AlgorithmOptions{};
  options.mapper.final_iterations = 1000000;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_EQ(error, "mapper.final_iterations: 1e+06 is outside the plausible range [1, 1000]");
}

// docs/plausible_ranges.md holds the table as the code has it.
TEST(OptionRangesTest, TheDocumentHoldsTheTable) {
  const std::string path = std::string(PARKSLAM_DOCS_DIR) + "/plausible_ranges.md";
  std::ifstream in(path);
  ASSERT_TRUE(in) << path;
  std::stringstream text;
  text << in.rdbuf();
  const std::string doc = text.str();
  const std::string begin = "<!-- option ranges: begin -->\n";
  const std::string end = "<!-- option ranges: end -->";
  const std::size_t from = doc.find(begin);
  const std::size_t to = doc.find(end);
  ASSERT_NE(from, std::string::npos) << path << " has no '" << begin << "'";
  ASSERT_NE(to, std::string::npos) << path << " has no '" << end << "'";
  const std::string table = doc.substr(from + begin.size(), to - from - begin.size());
  EXPECT_EQ(table, OptionRangesMarkdown())
      << "replace the table in " << path << " by `parkslam map --dump-ranges`";
}

}  // namespace
}  // namespace parkslam
