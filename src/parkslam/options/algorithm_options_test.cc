#include "parkslam/options/algorithm_options.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

namespace parkslam {
namespace {

// Walks every field of the options (nested parts through their own
// VisitFields) and, for the field numbered `target`, makes its value
// absurd: NaN, a billion below zero or 1e308 for a number, a billion
// below or above zero for a count. Counts the fields and records the dotted path of the one it
// changed.
struct Spoiler {
  int target = -1;
  enum class Absurd { kNan, kMinusBillion, kHuge } absurd = Absurd::kNan;
  int count = 0;
  std::string prefix;
  std::string spoiled;

  template <typename T>
  void operator()(const char* name, T& value) {
    const std::string path = prefix.empty() ? name : prefix + "." + name;
    if constexpr (requires(Spoiler & s) { value.VisitFields(s); }) {
      const std::string outer = prefix;
      prefix = path;
      value.VisitFields(*this);
      prefix = outer;
    } else if constexpr (std::is_same_v<T, double> || std::is_same_v<T, float> ||
                         std::is_same_v<T, int>) {
      if (count++ != target) return;
      spoiled = path;
      if constexpr (std::is_floating_point_v<T>) {
        value = absurd == Absurd::kNan            ? std::numeric_limits<T>::quiet_NaN()
                : absurd == Absurd::kMinusBillion ? T(-1e9)
                                                  : std::numeric_limits<T>::max();
      } else {
        value = absurd == Absurd::kHuge ? 1000000000 : -1000000000;
      }
    }
  }
};

// Issue: a bad value in a --config file must be rejected with the key that
// holds it ("mapper.null_weight: ..."), never with a group's name.
TEST(AlgorithmOptionsTest, EveryAbsurdNumberIsRejectedByItsOwnKey) {
  AlgorithmOptions defaults;
  std::string error;
  ASSERT_TRUE(defaults.IsValid(&error)) << error;
  Spoiler counter;
  defaults.VisitFields(counter);
  ASSERT_GT(counter.count, 100);
  std::printf("%d numbers in the algorithm options\n", counter.count);
  std::vector<std::string> wrong;
  using Absurd = Spoiler::Absurd;
  for (const Absurd absurd : {Absurd::kNan, Absurd::kMinusBillion, Absurd::kHuge}) {
    for (int k = 0; k < counter.count; ++k) {
      AlgorithmOptions options;
      Spoiler spoiler;
      spoiler.target = k;
      spoiler.absurd = absurd;
      options.VisitFields(spoiler);
      error.clear();
      if (options.IsValid(&error)) {
        const char* what = absurd == Absurd::kNan            ? " = nan"
                           : absurd == Absurd::kMinusBillion ? " = -1e9"
                                                             : " = 1e308 (1e9 for a count)";
        wrong.push_back(spoiler.spoiled + what + ": accepted");
      } else if (error.rfind(spoiler.spoiled + ": ", 0) != 0) {
        wrong.push_back(spoiler.spoiled + ": \"" + error + "\"");
      }
    }
  }
  std::string list;
  for (const std::string& w : wrong) list += "\n  " + w;
  EXPECT_TRUE(wrong.empty()) << wrong.size() << " of " << 3 * counter.count << " cases:" << list;
}

TEST(AlgorithmOptionsTest, NestedPartsAreNamedByTheirKeys) {
  AlgorithmOptions options;
  options.front_end.learned_slots.pairing.max_entrance_m = 1.0;
  std::string error;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_EQ(error,
            "front_end.learned_slots.pairing.max_entrance_m: must be greater than min_entrance_m");
  options = AlgorithmOptions{};
  options.mapper.null_weight = 2.0;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_EQ(error, "mapper.null_weight: 2 is outside the plausible range (0, 1]");
}

}  // namespace
}  // namespace parkslam
