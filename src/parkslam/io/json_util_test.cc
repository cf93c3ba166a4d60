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
  EXPECT_THAT(message, HasSubstr("doc.json:3: a[2]: invalid JSON: at line 1, column 12"));
  EXPECT_THAT(ErrorParsing(R"({"a": NaN})"), HasSubstr("doc.json:3: a: invalid JSON: "));
}

// The parser's own words ("[json.exception.parse_error.101] ...") never
// reach the user: each kind of bad text is said in plain words, with where.
TEST(ParseJsonTest, SaysWhatIsWrongInItsOwnWords) {
  const auto error_of = [](const std::string& text) {
    return ErrorOf([&] { ParseJson(text, "doc.json", 0); });
  };
  EXPECT_THAT(error_of("{\"a\": NaN}"),
              HasSubstr("doc.json: a: invalid JSON: at line 1, column 7: NaN and Infinity are not "
                        "JSON numbers"));
  EXPECT_THAT(error_of("{\n \"a\": -Infinity}"), HasSubstr("line 2, column"));
  EXPECT_THAT(error_of("{\"a\": -Infinity}"), HasSubstr("NaN and Infinity"));
  EXPECT_THAT(error_of("{\"slots\": [1, 2"), HasSubstr("ends before its value does"));
  EXPECT_THAT(error_of(""), HasSubstr("empty: no JSON value"));
  EXPECT_THAT(error_of(std::string("{\0\"\0a\0\"\0", 8)), HasSubstr("not UTF-8 text"));
  EXPECT_THAT(error_of("{\"a\": 1}}"), HasSubstr("unexpected '}'"));
  EXPECT_THAT(error_of("[1e999]"), HasSubstr("the number '1e999' is beyond the range"));
  for (const std::string text : {"{\"a\": NaN}", "[1, 2", "", "{\"a\": 1}}", "[1e999]", "\xff"}) {
    EXPECT_THAT(error_of(text), ::testing::Not(HasSubstr("json.exception"))) << text;
  }
}

}  // namespace
}  // namespace parkslam::io::json_util
