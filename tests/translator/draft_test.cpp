// Drafting an action model from words (translator/draft.h) against the mock endpoint, with the
// recorded answers of tests/recordings/draft: a good draft, one the repair fixes, one that stays
// broken.
#include "translator/draft.h"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "../planner/test_util.h"
#include "mock_llm.h"
#include "planner/model/domain.h"

namespace ctb {
namespace {

using testing::MockLlmServer;
using testing::MockReply;

const char* kDescription =
    "two drones that take off in 5 s and fly to A or B in 20 s; the hangar door must be open to "
    "take off";

std::string Recorded(const std::string& name) {
  std::ifstream in(testing::SourceDir() + "/tests/recordings/draft/" + name);
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_FALSE(ss.str().empty()) << name;
  return ss.str();
}

std::unique_ptr<LlmClient> Client(const MockLlmServer& m) {
  LlmConfig c;
  c.base_url = m.BaseUrl();
  c.api_key = "sk-test";
  c.model = "mock-model";
  c.timeout_ms = 3000;
  return MakeHttpClient(c);
}

DraftOptions Options(int max_repairs = 2) {
  DraftOptions o;
  o.max_repairs = max_repairs;
  o.prompts_dir = testing::SourceDir() + "/prompts";
  return o;
}

TEST(Draft, AGoodDraftComesBackWithRestatementAndQuestions) {
  MockLlmServer m;
  m.Then(MockReply::Chat(Recorded("good.txt")));
  auto client = Client(m);
  auto r = Draft(kDescription, *client, Options());
  ASSERT_TRUE(std::holds_alternative<DraftResult>(r)) << std::get<Error>(r).ToString();
  const DraftResult& d = std::get<DraftResult>(r);
  EXPECT_EQ(d.llm_calls, 1);
  EXPECT_EQ(d.repairs, 0);
  EXPECT_EQ(d.action_model["name"], "hangar_drones");
  EXPECT_TRUE(d.action_model["automata"][0].contains("template"));  // kept as written
  EXPECT_NE(d.restatement.find("drone1"), std::string::npos);
  ASSERT_EQ(d.questions.size(), 2u);
  Diagnostics diags;
  auto dom = LoadDomain(d.action_model, diags);
  ASSERT_TRUE(dom);
  EXPECT_EQ(dom->automata.size(), 3u);
  Json j = DraftJson(d);
  EXPECT_TRUE(j.contains("action_model") && j.contains("restatement") && j.contains("questions"));
  // The request: the format described, the description in the user turn.
  auto reqs = m.Requests();
  ASSERT_EQ(reqs.size(), 1u);
  EXPECT_NE(reqs[0].body["messages"][0]["content"].get<std::string>().find("\"template\""),
            std::string::npos);
  EXPECT_NE(reqs[0].body["messages"][1]["content"].get<std::string>().find(kDescription),
            std::string::npos);
}

TEST(Draft, ABrokenDraftIsRepairedQuotingPointerAndMessage) {
  MockLlmServer m;
  m.Then(MockReply::Chat(Recorded("broken.txt")));
  m.Then(MockReply::Chat(Recorded("good.txt")));
  auto client = Client(m);
  auto r = Draft(kDescription, *client, Options());
  ASSERT_TRUE(std::holds_alternative<DraftResult>(r)) << std::get<Error>(r).ToString();
  EXPECT_EQ(std::get<DraftResult>(r).repairs, 1);
  auto reqs = m.Requests();
  ASSERT_EQ(reqs.size(), 2u);
  std::string repair = reqs[1].body["messages"].back()["content"];
  EXPECT_NE(repair.find("/automata/0/transitions/0/guard: in instance 'drone1' (k=1): "),
            std::string::npos) << repair;
  EXPECT_NE(repair.find("unknown location 'opened'"), std::string::npos) << repair;
  EXPECT_NE(repair.find("/automata/0/transitions/3/duration: "), std::string::npos) << repair;
  EXPECT_NE(repair.find("/automata/1/transitions/1/to: unknown location 'shut'"), std::string::npos)
      << repair;
  EXPECT_EQ(reqs[1].body["messages"][2]["role"], "assistant");
}

TEST(Draft, ADraftThatStaysBrokenIsUnprocessableWithEveryError) {
  MockLlmServer m;
  for (int k = 0; k < 3; ++k) m.Then(MockReply::Chat(Recorded("broken.txt")));
  auto client = Client(m);
  auto r = Draft(kDescription, *client, Options(2));
  ASSERT_TRUE(std::holds_alternative<Error>(r));
  const Error& e = std::get<Error>(r);
  EXPECT_EQ(e.code, ErrorCode::kUnprocessable);
  EXPECT_EQ(m.Requests().size(), 3u);
  std::set<std::string> pointers;
  for (const auto& d : e.details) pointers.insert(d.pointer);
  EXPECT_TRUE(pointers.count("/automata/0/transitions/0/guard"));
  EXPECT_TRUE(pointers.count("/automata/0/transitions/3/duration"));
  EXPECT_TRUE(pointers.count("/automata/1/transitions/1/to"));
}

TEST(Draft, NotJsonAndAnEmptyDescription) {
  MockLlmServer m;
  m.Then(MockReply::Chat("I would need to know more about the drones."));
  m.Then(MockReply::Chat(Recorded("good.txt")));
  auto client = Client(m);
  auto r = Draft(kDescription, *client, Options(1));
  ASSERT_TRUE(std::holds_alternative<DraftResult>(r)) << std::get<Error>(r).ToString();
  auto empty = Draft("  ", *client, Options());
  ASSERT_TRUE(std::holds_alternative<Error>(empty));
  EXPECT_EQ(std::get<Error>(empty).code, ErrorCode::kInvalidInput);
  EXPECT_EQ(std::get<Error>(empty).details.at(0).pointer, "/description");
}

}  // namespace
}  // namespace ctb
