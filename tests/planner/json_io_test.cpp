#include "planner/model/json_io.h"

#include <gtest/gtest.h>

#include "test_util.h"

namespace ctb {
namespace {

using testing::HasError;

std::optional<Json> P(const std::string& text, Diagnostics& d, ParseLimits limits = {}) {
  return ParseJsonStrict(text, d, limits);
}

TEST(ParseJsonStrict, AcceptsAnObject) {
  Diagnostics d;
  auto j = P(R"({"a": [1, 2.5, "x", null, true]})", d);
  ASSERT_TRUE(j);
  EXPECT_TRUE(d.ok());
  EXPECT_EQ((*j)["a"][2], "x");
}

TEST(ParseJsonStrict, RejectsEmptyAndBlankInput) {
  for (std::string text : {"", "   \n\t "}) {
    Diagnostics d;
    EXPECT_FALSE(P(text, d));
    EXPECT_TRUE(HasError(d, "", "empty input"));
  }
}

TEST(ParseJsonStrict, RejectsTruncatedInputWithOffset) {
  Diagnostics d;
  EXPECT_FALSE(P(R"({"a": [1, 2)", d));
  ASSERT_EQ(d.errors().size(), 1u);
  EXPECT_NE(d.errors()[0].message.find("not valid JSON"), std::string::npos);
  EXPECT_TRUE(d.errors()[0].offset.has_value());
}

TEST(ParseJsonStrict, RejectsMissingCommaAtItsOffset) {
  Diagnostics d;
  std::string text = R"({"a": 1 "b": 2})";
  EXPECT_FALSE(P(text, d));
  ASSERT_EQ(d.errors().size(), 1u);
  // nlohmann points just past the unexpected token "b"
  EXPECT_EQ(d.errors()[0].offset, text.find("\"b\"") + 2);
}

TEST(ParseJsonStrict, RejectsNaNAndInfinityTokens) {
  for (std::string text : {R"({"a": NaN})", R"({"a": Infinity})", R"({"a": -Infinity})"}) {
    Diagnostics d;
    EXPECT_FALSE(P(text, d)) << text;
  }
}

TEST(ParseJsonStrict, RejectsDeepNestingWithoutRecursing) {
  std::string deep(100000, '[');
  deep += std::string(100000, ']');
  Diagnostics d;
  EXPECT_FALSE(P(deep, d));
  EXPECT_TRUE(HasError(d, "", "nested deeper than 64", std::size_t{64}));
}

TEST(ParseJsonStrict, BracketsInsideStringsDoNotCountAsNesting) {
  Diagnostics d;
  std::string text = "{\"a\": \"" + std::string(1000, '[') + "\\\"" + "\"}";
  EXPECT_TRUE(P(text, d)) << testing::AllErrors(d);
}

TEST(ParseJsonStrict, RejectsDuplicateKeys) {
  Diagnostics d;
  EXPECT_FALSE(P(R"({"a": 1, "b": {"c": 1, "c": 2}})", d));
  EXPECT_TRUE(HasError(d, "", "duplicate key \"c\""));
}

TEST(ParseJsonStrict, SameKeyInSiblingObjectsIsFine) {
  Diagnostics d;
  EXPECT_TRUE(P(R"([{"a": 1}, {"a": 2}])", d));
}

TEST(ParseJsonStrict, RejectsInputOverTheSizeLimit) {
  Diagnostics d;
  ParseLimits limits;
  limits.max_bytes = 10;
  EXPECT_FALSE(P(R"({"abcdefghijkl": 1})", d, limits));
  EXPECT_TRUE(HasError(d, "", "more than the limit"));
}

TEST(ParseJsonStrict, RejectsInvalidUtf8) {
  Diagnostics d;
  EXPECT_FALSE(P("{\"a\": \"\xff\xfe\"}", d));
}

TEST(AsNonNegative, RejectsOverflowNegativeAndNonNumbers) {
  Diagnostics d;
  auto j = P(R"({"big": 1e999, "neg": -1, "str": "5", "ok": 2.5})", d);
  if (!j) {  // nlohmann may refuse 1e999 outright: that is also a clear rejection
    EXPECT_FALSE(d.ok());
    return;
  }
  EXPECT_FALSE(AsNonNegative((*j)["big"], "/big", d));
  EXPECT_TRUE(HasError(d, "/big", "not finite"));
  EXPECT_FALSE(AsNonNegative((*j)["neg"], "/neg", d));
  EXPECT_TRUE(HasError(d, "/neg", "must not be negative"));
  EXPECT_FALSE(AsNonNegative((*j)["str"], "/str", d));
  EXPECT_TRUE(HasError(d, "/str", "expected a number, got string"));
  EXPECT_EQ(AsNonNegative((*j)["ok"], "/ok", d), 2.5);
}

TEST(ObjectReader, ReportsUnknownKeysAtTheirPointer) {
  Diagnostics d;
  auto j = P(R"({"good": 1, "a/b": 2})", d);
  ObjectReader r(*j, "/x", d);
  r.CheckKeys({"good"});
  EXPECT_TRUE(HasError(d, "/x/a~1b", "unknown field \"a/b\""));
}

TEST(ReadJsonFile, MissingFileIsAnError) {
  Diagnostics d;
  EXPECT_FALSE(ReadJsonFile("/nonexistent/file.json", d));
  EXPECT_TRUE(HasError(d, "", "cannot open file"));
}

}  // namespace
}  // namespace ctb
