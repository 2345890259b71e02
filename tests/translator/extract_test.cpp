// Finding and reading the JSON of an answer.
#include "translator/extract.h"

#include <gtest/gtest.h>

#include "translator/text.h"

namespace ctb {
namespace {

std::string Notes(const Extraction& x) {
  std::string s;
  for (const auto& n : x.notes) s += n.message + "\n";
  return s;
}

TEST(FindJson, FencesProseAndNothing) {
  EXPECT_EQ(*FindJson("```json\n{\"a\": 1}\n```"), "{\"a\": 1}");
  EXPECT_EQ(*FindJson("Sure! {\"a\": {\"b\": 2}} Hope it helps."), "{\"a\": {\"b\": 2}}");
  EXPECT_EQ(*FindJson("```\nnot json\n```\nthen {\"x\": 1}"), "{\"x\": 1}");
  EXPECT_FALSE(FindJson("no braces here"));
  EXPECT_EQ(*FindJson("cut {\"a\": "), "{\"a\": ");
}

TEST(FindJson, BracesInsideStringsDoNotCount) {
  EXPECT_EQ(*FindJson("{\"a\": \"}{\", \"initial_state\": {}} after"),
            "{\"a\": \"}{\", \"initial_state\": {}}");
  EXPECT_EQ(*FindJson("{'a': '}', 'initial_state': 1}"), "{'a': '}', 'initial_state': 1}");
}

TEST(FindJson, TheLastStatePlanWinsOverDraftsAndProseBraces) {
  std::string text = "draft {\"initial_state\": 1} final {\"initial_state\": 2} see {i}";
  EXPECT_EQ(*FindJson(text), "{\"initial_state\": 2}");
}

TEST(StripThinking, BlocksUnclosedAndLoneClosingTags) {
  EXPECT_EQ(StripThinking("<think>{x}</think>{\"a\": 1}"), "{\"a\": 1}");
  EXPECT_EQ(StripThinking("a<thinking>b</thinking>c"), "ac");
  EXPECT_EQ(StripThinking("reasoning {x}</think>{\"a\": 1}"), "{\"a\": 1}");
  EXPECT_EQ(StripThinking("{\"a\": 1}<think>never closed"), "{\"a\": 1}");
  bool stripped = true;
  EXPECT_EQ(StripThinking("plain", &stripped), "plain");
  EXPECT_FALSE(stripped);
}

TEST(RelaxJson, EachSlipIsMendedAndNamedOnce) {
  std::vector<std::string> applied;
  std::string r = RelaxJson("{'a': True, // c\n \"b\": [1, 2,], /* x */ \"c\": None,}", applied);
  EXPECT_EQ(Json::parse(r), Json::parse("{\"a\": true, \"b\": [1, 2], \"c\": null}"));
  EXPECT_EQ(applied.size(), 4u);
  applied.clear();
  r = RelaxJson(
      "{\xE2\x80\x9C"
      "a\xE2\x80\x9D: \xE2\x80\x9C"
      "say \xE2\x80\x98hi\xE2\x80\x99\xE2\x80\x9D}",
      applied);
  EXPECT_EQ(Json::parse(r)["a"], "say \xE2\x80\x98hi\xE2\x80\x99");
  applied.clear();
  r = RelaxJson("{\"a\": \"line1\nline2\"}", applied);
  EXPECT_EQ(Json::parse(r)["a"], "line1\nline2");
  ASSERT_EQ(applied.size(), 1u);
  applied.clear();
  EXPECT_EQ(RelaxJson("{\"x\": \"it's // not a comment, ]\"}", applied),
            "{\"x\": \"it's // not a comment, ]\"}");
  EXPECT_TRUE(applied.empty());
}

TEST(ExtractJson, StrictJsonNeedsNoNote) {
  Extraction x = ExtractJson("{\"initial_state\": {}}");
  ASSERT_TRUE(x.json);
  EXPECT_TRUE(x.notes.empty());
}

TEST(ExtractJson, TolerantParsingIsReported) {
  Extraction x = ExtractJson("{\"initial_state\": {},}");
  ASSERT_TRUE(x.json);
  EXPECT_NE(Notes(x).find("trailing commas"), std::string::npos);
}

TEST(ExtractJson, DoubleEncodedAnswerIsDecoded) {
  Extraction x = ExtractJson("\"{\\\"initial_state\\\": {}}\"");
  ASSERT_TRUE(x.json);
  EXPECT_TRUE(x.json->is_object());
  EXPECT_NE(Notes(x).find("double-encoded"), std::string::npos);
}

TEST(ExtractJson, AParseErrorQuotesTheTextInsteadOfAnOffset) {
  Extraction x = ExtractJson("{\"initial_state\": {\"comp\": \"compOff\" \"proj\": 1}}");
  ASSERT_FALSE(x.json);
  ASSERT_FALSE(x.errors.empty());
  EXPECT_FALSE(x.errors[0].offset);
  EXPECT_NE(x.errors[0].message.find("near: `"), std::string::npos) << x.errors[0].message;
  EXPECT_NE(x.errors[0].message.find("\"compOff\" \"proj\""), std::string::npos)
      << x.errors[0].message;
  EXPECT_EQ(x.errors[0].message.find("last read"), std::string::npos);
}

TEST(ExtractJson, AParseErrorOnANonAsciiByteGivesValidUtf8) {
  Extraction x = ExtractJson("{\"a\": \xC2\xBFtrue?}");
  ASSERT_FALSE(x.json);
  ASSERT_FALSE(x.errors.empty());
  for (const auto& e : x.errors) {
    EXPECT_EQ(ValidUtf8(e.message), e.message);
    EXPECT_NO_THROW((void)Json(e.message).dump());
  }
}

TEST(ExtractJson, NoJsonQuotesTheModelsWords) {
  Extraction x = ExtractJson("I'm sorry, I cannot do that.");
  ASSERT_EQ(x.errors.size(), 1u);
  EXPECT_EQ(x.errors[0].message,
            "the answer holds no JSON object; it reads: \"I'm sorry, I cannot do that.\"");
  x = ExtractJson(" \n");
  ASSERT_EQ(x.errors.size(), 1u);
  EXPECT_EQ(x.errors[0].message, "the answer was empty");
}

TEST(ExtractJson, ACutOffAnswerSaysSo) {
  Extraction x = ExtractJson("{\"initial_state\": {\"comp\": \"comp");
  ASSERT_FALSE(x.json);
  EXPECT_NE(x.errors.back().message.find("cut off"), std::string::npos);
}

}  // namespace
}  // namespace ctb
