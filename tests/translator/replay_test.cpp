// The shipped recordings of the thesis' test prompts, replayed with no network: every prompt
// becomes a valid state plan, and the natural-language path runs on into a verified plan.
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "../planner/test_util.h"
#include "planner/solve/solve.h"
#include "translator/pipeline.h"

namespace ctb {
namespace {

Json Script() {
  std::ifstream in(ctb::testing::SourceDir() + "/tests/recordings/thesis_answers.json");
  std::stringstream ss;
  ss << in.rdbuf();
  return Json::parse(ss.str());
}

std::variant<TranslateResult, Error> Replay(const Json& c) {
  auto client = MakeReplayClient(ctb::testing::SourceDir() + "/tests/recordings/thesis", "gpt-4o");
  if (auto* e = std::get_if<Error>(&client)) return *e;
  TranslateOptions o;
  o.prompting = *ParsePrompting(c["prompting"]);
  o.prompts_dir = ctb::testing::SourceDir() + "/prompts";
  return Translate(ctb::testing::ShippedDomain(c["domain"]), c["command"],
                   *std::get<std::unique_ptr<LlmClient>>(client), o);
}

TEST(Replay, EveryThesisPromptBecomesAValidStatePlanOffline) {
  Json script = Script();
  ASSERT_GE(script.size(), 7u);
  for (const auto& c : script) {
    auto r = Replay(c);
    ASSERT_TRUE(std::holds_alternative<TranslateResult>(r))
        << c["name"] << ": " << std::get<Error>(r).ToString()
        << "\n(after changing a prompt, regenerate the recordings: see tests/recordings/README.md)";
    const auto& t = std::get<TranslateResult>(r);
    EXPECT_EQ(t.llm_calls, static_cast<int>(c["answers"].size())) << c["name"];
    EXPECT_EQ(t.reasoning.empty(), c["prompting"] == "direct") << c["name"];
    Diagnostics d;
    EXPECT_TRUE(LoadStatePlan(t.state_plan, ctb::testing::ShippedDomain(c["domain"]), d)) << c["name"];
  }
}

TEST(Replay, TheDirectSlipIsRepairedFromTheRecording) {
  int found = 0;
  for (const auto& c : Script()) {
    if (c["name"] != "presentation_test1_direct") continue;
    ++found;
    auto r = Replay(c);
    ASSERT_TRUE(std::holds_alternative<TranslateResult>(r));
    EXPECT_EQ(std::get<TranslateResult>(r).repairs, 1);
    EXPECT_EQ(std::get<TranslateResult>(r).state_plan["constraints"]["temporal"]["first60"]
                                                     ["accepting_event1_constraint"],
              "projl[i]==projOff");
  }
  EXPECT_EQ(found, 1) << "the recording script lost its case";
}

TEST(Replay, NaturalLanguageToVerifiedPlan) {
  int found = 0;
  for (const auto& c : Script()) {
    if (c["name"] != "presentation_test1_cot" && c["name"] != "search_rescue_test2") continue;
    ++found;
    auto r = Replay(c);
    ASSERT_TRUE(std::holds_alternative<TranslateResult>(r));
    const Domain& d = ctb::testing::ShippedDomain(c["domain"]);
    Diagnostics diags;
    auto sp = LoadStatePlan(std::get<TranslateResult>(r).state_plan, d, diags);
    ASSERT_TRUE(sp);
    SolveOptions o;
    o.time_limit_ms = 120000;
    auto s = SolveDocument(d, *sp, o);
    ASSERT_TRUE(std::holds_alternative<Json>(s)) << std::get<Error>(s).ToString();
    const Json& t = std::get<Json>(s);
    EXPECT_EQ(t["status"], "optimal") << c["name"];
    EXPECT_EQ(t["verified"], true);
    if (c["name"] == "search_rescue_test2") EXPECT_EQ(t["objective"]["value"], 11);
    else EXPECT_EQ(t["goal_reached_at"], 2430);
  }
  EXPECT_EQ(found, 2) << "the recording script lost a case";
}

TEST(Replay, AnUnrecordedCommandIsAClearMiss) {
  Json c = Script()[0];
  c["command"] = "Turn on the projector and leave it on.";
  auto r = Replay(c);
  ASSERT_TRUE(std::holds_alternative<Error>(r));
  EXPECT_EQ(std::get<Error>(r).code, ErrorCode::kUnavailable);
}

}  // namespace
}  // namespace ctb
