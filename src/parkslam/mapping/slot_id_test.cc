#include "parkslam/mapping/slot_id.h"

#include <gtest/gtest.h>

namespace parkslam::mapping {
namespace {

DigitReading Digit(std::vector<DigitHypothesis> h) { return DigitReading{std::move(h)}; }

TEST(SlotIdTest, FullHypothesesAreProductsSortedByProbability) {
  const SlotIdReading reading{{Digit({{'3', 0.8}, {'8', 0.2}}), Digit({{'9', 0.6}, {'8', 0.3}})}};
  const auto h = FullIdHypotheses(reading, 0.05);
  ASSERT_EQ(h.size(), 4u);
  EXPECT_EQ(h[0].id, "39");
  EXPECT_NEAR(h[0].probability, 0.48, 1e-12);
  EXPECT_EQ(h[1].id, "38");
  EXPECT_NEAR(h[1].probability, 0.24, 1e-12);
  EXPECT_EQ(h[3].id, "88");
  EXPECT_NEAR(h[3].probability, 0.06, 1e-12);
}

TEST(SlotIdTest, MinimumProbabilityPrunesJustBelowAndKeepsJustAbove) {
  const SlotIdReading reading{{Digit({{'3', 0.8}, {'8', 0.2}}), Digit({{'9', 0.6}, {'8', 0.3}})}};
  EXPECT_EQ(FullIdHypotheses(reading, 0.0601).size(), 3u);  // 88 at 0.06 dropped
  EXPECT_EQ(FullIdHypotheses(reading, 0.0599).size(), 4u);
}

TEST(SlotIdTest, PartialAndEmptyReadingsHaveNoFullHypotheses) {
  const SlotIdReading partial{{DigitReading{}, Digit({{'8', 0.9}})}};
  EXPECT_TRUE(FullIdHypotheses(partial, 0.01).empty());
  EXPECT_EQ(PartialPattern(partial), "?8");
  EXPECT_TRUE(FullIdHypotheses(SlotIdReading{}, 0.01).empty());
  EXPECT_EQ(PartialPattern(SlotIdReading{}), "");
}

TEST(SlotIdTest, PatternMatching) {
  EXPECT_TRUE(MatchesPattern("38", "?8"));
  EXPECT_TRUE(MatchesPattern("38", "3?"));
  EXPECT_FALSE(MatchesPattern("39", "?8"));
  EXPECT_FALSE(MatchesPattern("138", "?8"));
  EXPECT_TRUE(MatchesPattern("38", "38"));
}

}  // namespace
}  // namespace parkslam::mapping
