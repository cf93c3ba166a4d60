#include "parkslam/io/json_util.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "parkslam/io/io_error.h"
#include "parkslam/io/test_util.h"

namespace parkslam::io::json_util {
namespace {

using testing::ErrorOf;
using ::testing::HasSubstr;

std::string ErrorParsing(const std::string& text) {
  return ErrorOf([&] { ParseJson(text, "doc.json", 3); });
}

TEST(ParseJsonTest, ParsesValidJson) {
  const Json json = ParseJson(R"({"a": [1, 2.5e3]})", "doc.json", 0);
  EXPECT_EQ(json["a"][1].get<double>(), 2500.0);
}

// nlohmann gives no position for a number beyond the range of a double: the
// message names the path of the value, spelled like JsonPath.
TEST(ParseJsonTest, NumberTooLargeForADoubleNamesItsPath) {
  EXPECT_THAT(ErrorParsing(R"({"a": [{"b": 1}, {"c": [1, [2], 1e999]}]})"),
              HasSubstr("doc.json:3: a[1].c[2]: invalid JSON: "));
  EXPECT_THAT(ErrorParsing(R"({"a": {"b": [1]}, "c": -1e999})"),
              HasSubstr("doc.json:3: c: invalid JSON: "));
  EXPECT_THAT(ErrorParsing("[0, 1e999]"), HasSubstr("doc.json:3: [1]: invalid JSON: "));
  EXPECT_THAT(ErrorParsing("1e999"), HasSubstr("doc.json:3: invalid JSON: "));
  EXPECT_THAT(ErrorParsing("1e999"), HasSubstr("'1e999'"));
}

TEST(ParseJsonTest, SyntaxErrorKeepsTheParsersPosition) {
  const std::string message = ErrorParsing(R"({"a": [1, 2)");
  EXPECT_THAT(message, HasSubstr("doc.json:3: invalid JSON: "));
  EXPECT_THAT(message, HasSubstr("line 1, column"));
  EXPECT_THAT(ErrorParsing(R"({"a": NaN})"), HasSubstr("doc.json:3: invalid JSON: "));
}

}  // namespace
}  // namespace parkslam::io::json_util
