// The corpus of quirky LLM answers (quirks/quirks.json, written by quirks/make_quirks.py), each
// replayed through the real HTTP client against the loopback mock endpoint in two scenarios:
// the endpoint gives a good answer to the repair request, or repeats its mistake. In both: no
// crash, no plan accepted with another meaning, and a clear error otherwise.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "../planner/test_util.h"
#include "mock_llm.h"
#include "translator/pipeline.h"
#include "translator/text.h"

namespace ctb {
// A namespace of its own: the test executable's unity build puts files with same-named
// helpers side by side.
namespace quirks_test {
namespace {

using testing::MockLlmServer;
using testing::MockReply;

const char* kCommand1 =
    "The computer and projector start in the off state, and the connection is disconnected. The "
    "projector should turn on and stay on for 1800 seconds, following which everything should "
    "turn off within 600 seconds. In addition, the projector should turn on within 60 seconds.";

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

Json Corpus() {
  return Json::parse(ReadFile(ctb::testing::SourceDir() + "/tests/translator/quirks/quirks.json"));
}

Json GoodPlan() {
  return Json::parse(ReadFile(ctb::testing::ConfigDir() + "/examples/presentation/test1_cot.json"));
}

MockReply Reply(const Json& c) {
  if (!c.contains("message")) return MockReply::Chat(c["content"].get<std::string>());
  Json j = {{"id", "mock"},
            {"object", "chat.completion"},
            {"choices", {{{"index", 0}, {"message", c["message"]}, {"finish_reason", "stop"}}}}};
  return {200, j.dump(), {}, 0};
}

std::string AllText(const Error& e) {
  std::string s = e.message + "\n";
  for (const auto& d : e.details) s += d.ToString() + "\n";
  return s;
}

std::string AllWarnings(const TranslateResult& t) {
  std::string s;
  for (const auto& w : t.warnings) s += w.ToString() + "\n";
  return s;
}

enum class Scenario { kRepairs, kRepeats };

void RunCase(const Json& c, Scenario scenario) {
  const std::string name = c["name"];
  const std::string cls = c["class"];
  SCOPED_TRACE(name +
               (scenario == Scenario::kRepairs ? " (endpoint repairs)" : " (endpoint repeats)"));
  const Json good = c.contains("good") ? c["good"] : GoodPlan();
  MockLlmServer m;
  m.Then(Reply(c));
  for (int i = 0; i < 2; ++i)
    m.Then(scenario == Scenario::kRepairs ? MockReply::Chat(good.dump(2)) : Reply(c));
  LlmConfig cfg;
  cfg.base_url = m.BaseUrl();
  cfg.api_key = "sk-test-secret-key-1234";
  cfg.model = "mock-model";
  cfg.timeout_ms = 5000;
  auto client = MakeHttpClient(cfg);
  TranslateOptions o;
  o.prompting = Prompting::kDirect;
  o.max_repairs = 2;
  o.prompts_dir = ctb::testing::SourceDir() + "/prompts";
  const std::string command = c.value("command", std::string(kCommand1));
  auto r = Translate(ctb::testing::ShippedDomain("presentation"), command, *client, o);

  if (auto* e = std::get_if<Error>(&r)) {
    // Every error is for people: valid UTF-8, serialisable, without the key, bounded.
    std::string text = AllText(*e);
    EXPECT_EQ(ValidUtf8(text), text);
    EXPECT_EQ(text.find("sk-test"), std::string::npos);
    EXPECT_NO_THROW((void)Json(text).dump());
    for (const auto& d : e->details) EXPECT_LT(d.message.size(), 700u) << d.message;
  }
  bool expect_error = cls == "judgement" && scenario == Scenario::kRepeats;
  if (expect_error) {
    ASSERT_TRUE(std::holds_alternative<Error>(r))
        << "a plan was accepted: " << std::get<TranslateResult>(r).state_plan.dump();
    const Error& e = std::get<Error>(r);
    EXPECT_EQ(e.code, ErrorCode::kUnprocessable) << AllText(e);
    EXPECT_NE(AllText(e).find(c["error"].get<std::string>()), std::string::npos) << AllText(e);
    EXPECT_EQ(m.Requests().size(), 3u);
    return;
  }
  ASSERT_TRUE(std::holds_alternative<TranslateResult>(r)) << AllText(std::get<Error>(r));
  const TranslateResult& t = std::get<TranslateResult>(r);
  EXPECT_NO_THROW((void)WarningsJson(t.warnings).dump());
  if (cls == "normalised") {
    EXPECT_EQ(t.repairs, 0) << AllWarnings(t);
    EXPECT_EQ(t.state_plan, good) << t.state_plan.dump(2);
    for (const auto& w : c.value("warn", Json::array()))
      EXPECT_NE(AllWarnings(t).find(w.get<std::string>()), std::string::npos)
          << "missing warning '" << w.get<std::string>() << "' in:\n"
          << AllWarnings(t);
    if (!c.contains("warn")) EXPECT_TRUE(t.warnings.empty()) << AllWarnings(t);
  } else if (scenario == Scenario::kRepairs) {  // judgement or doubt, repaired
    EXPECT_EQ(t.repairs, 1);
    EXPECT_EQ(t.state_plan, good) << t.state_plan.dump(2);
    EXPECT_TRUE(t.warnings.empty()) << AllWarnings(t);
    // The repair request names the problem.
    std::string repair = m.Requests()[1].body["messages"].back()["content"];
    EXPECT_NE(repair.find("cannot be used"), std::string::npos);
  } else {  // doubt, repeated: accepted, the doubt reported
    EXPECT_EQ(t.repairs, 2);
    for (const auto& w : c["warn"])
      EXPECT_NE(AllWarnings(t).find(w.get<std::string>()), std::string::npos)
          << "missing warning '" << w.get<std::string>() << "' in:\n"
          << AllWarnings(t);
  }
}

TEST(TranslatorQuirks, TheCorpusHasAtLeastFortyAnswersOfEveryClass) {
  Json corpus = Corpus();
  EXPECT_GE(corpus.size(), 40u);
  std::map<std::string, int> per_class;
  for (const auto& c : corpus) ++per_class[c["class"].get<std::string>()];
  EXPECT_GE(per_class["normalised"], 20);
  EXPECT_GE(per_class["judgement"], 10);
  EXPECT_GE(per_class["doubt"], 2);
}

TEST(TranslatorQuirks, EveryAnswerWhenTheEndpointRepairs) {
  for (const auto& c : Corpus()) RunCase(c, Scenario::kRepairs);
}

TEST(TranslatorQuirks, EveryAnswerWhenTheEndpointRepeatsTheMistake) {
  for (const auto& c : Corpus()) RunCase(c, Scenario::kRepeats);
}

}  // namespace
}  // namespace quirks_test
}  // namespace ctb
