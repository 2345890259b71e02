// Normalisations of a parsed answer: each one applied is a warning with its pointer.
#include "translator/normalize_answer.h"

#include <gtest/gtest.h>

#include "../planner/test_util.h"

namespace ctb {
// A namespace of its own: the test executable's unity build puts files with same-named
// helpers side by side.
namespace normalize_answer_test {
namespace {

const Domain& Presentation() { return ctb::testing::ShippedDomain("presentation"); }

TEST(NormalizeOperators, OtherSpellingsOfAndOrNot) {
  std::vector<std::string> changes;
  EXPECT_EQ(NormalizeOperators("a[i]==x && b[i]==y || c[i]==z", Presentation(), changes),
            "a[i]==x /\\ b[i]==y \\/ c[i]==z");
  EXPECT_EQ(changes.size(), 2u);
  changes.clear();
  EXPECT_EQ(NormalizeOperators("a[i]==x \xE2\x88\xA7 b[i]==y \xE2\x88\xA8 c[i]\xE2\x89\xA0z",
                               Presentation(), changes),
            "a[i]==x /\\ b[i]==y \\/ c[i]!=z");
  changes.clear();
  EXPECT_EQ(NormalizeOperators("x and y AND z or w OR v", Presentation(), changes),
            "x /\\ y /\\ z \\/ w \\/ v");
  changes.clear();
  EXPECT_EQ(
      NormalizeOperators("!(projl[i]==projOn) /\\ projl[i]!=projOff", Presentation(), changes),
      "not (projl[i]==projOn) /\\ projl[i]!=projOff");
  changes.clear();
  EXPECT_EQ(NormalizeOperators("projl[i]==projOn /\\ brand[i]==x", Presentation(), changes),
            "projl[i]==projOn /\\ brand[i]==x");  // words containing "and" are names
  EXPECT_TRUE(changes.empty());
}

TEST(ParseDuration, NumbersAndUnambiguousUnits) {
  EXPECT_EQ(ParseDuration("30"), 30);
  EXPECT_EQ(ParseDuration(" 90s "), 90);
  EXPECT_EQ(ParseDuration("30 min"), 1800);
  EXPECT_EQ(ParseDuration("2 h"), 7200);
  EXPECT_EQ(ParseDuration("1.5 hours"), 5400);
  EXPECT_EQ(ParseDuration("500 ms"), 0.5);
  EXPECT_FALSE(ParseDuration("30 m"));  // minutes or metres: the repair loop asks
  EXPECT_FALSE(ParseDuration("soon"));
  EXPECT_FALSE(ParseDuration("-5"));
  EXPECT_FALSE(ParseDuration("10 days"));
}

TEST(NormalizeAnswer, WrappersDoubleEncodingOperatorsAndUnitsEachWarned) {
  Json inner = {{"initial_state", {{"comp", "compOff"}}},
                {"end_state", {{"goal_constraint", "compl[i+1]==compOn && projl[i+1]==projOn"}}},
                {"constraints",
                 {{"episodes", {{"On", {{"lower_bound", "30 min"}, {"upper_bound", 1800}}}}}}}};
  Json answer = {{"state_plan", inner.dump()}};
  std::vector<Diagnostic> notes;
  Json out = NormalizeAnswer(answer, Presentation(), notes);
  EXPECT_EQ(out["end_state"]["goal_constraint"], "compl[i+1]==compOn /\\ projl[i+1]==projOn");
  EXPECT_EQ(out["constraints"]["episodes"]["On"]["lower_bound"], 1800);
  ASSERT_EQ(notes.size(), 3u);
  EXPECT_NE(notes[0].message.find("wrapped in {\"state_plan\""), std::string::npos);
  EXPECT_EQ(notes[1].pointer, "/end_state/goal_constraint");
  EXPECT_EQ(notes[1].message, "read '&&' as '/\\'");
  EXPECT_EQ(notes[2].pointer, "/constraints/episodes/On/lower_bound");
  EXPECT_EQ(notes[2].message, "read the string \"30 min\" as 1800 seconds");
}

TEST(NormalizeAnswer, APlainPlanIsLeftAlone) {
  Json plan = ctb::testing::MustParse(
      "{\"initial_state\": {}, \"end_state\": {\"goal_constraint\": \"projl[i+1]==projOn\"}}");
  std::vector<Diagnostic> notes;
  EXPECT_EQ(NormalizeAnswer(plan, Presentation(), notes), plan);
  EXPECT_TRUE(notes.empty());
}

TEST(NormalizeAnswer, AnUnreadableBoundIsLeftForTheChecker) {
  Json plan = {{"constraints", {{"temporal", {{"T", {{"lower_bound", "a while"}}}}}}}};
  plan["initial_state"] = Json::object();
  std::vector<Diagnostic> notes;
  EXPECT_EQ(
      NormalizeAnswer(plan, Presentation(), notes)["constraints"]["temporal"]["T"]["lower_bound"],
      "a while");
  EXPECT_TRUE(notes.empty());
}

}  // namespace
}  // namespace normalize_answer_test
}  // namespace ctb
