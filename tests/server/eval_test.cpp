// POST /eval against the real server binary, the real minizinc and the loopback mock LLM
// (contract section 15): a translation that says the same as its reference (equivalent), one
// that is valid but means something else (not equivalent), answers that never parse (unparsed),
// JSON that never loads (invalid), and a check cut off by its time limit (unknown, never
// equivalent); the stream; a suite that is wrong is refused at its pointer before any LLM call.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "../translator/mock_llm.h"
#include "harness.h"

namespace ctb {
namespace {

using testing::MockLlmServer;
using testing::MockReply;

class EvalServer : public ctb::testing::ServerProcess {
 public:
  explicit EvalServer(std::vector<std::pair<std::string, std::string>> env)
      : ServerProcess(Json::object(), {}, std::move(env), "") {}
  ctb::testing::RecordingClient Client() const {
    ctb::testing::RecordingClient c("127.0.0.1", port());
    c.set_read_timeout(120, 0);
    return c;
  }
};

const char* kRescue1 = R"({
  "initial_state": {"robot1": "outside", "robot2": "outside", "door1": "closed", "door2": "closed", "door3": "open"},
  "end_state": {"maintenance_constraint": "true", "goal_constraint": "robot1[i+1]==rescuedPerson1"},
  "objective": "makespan"})";

Json Rescue(const std::string& goal) {
  Json j = Json::parse(kRescue1);
  j["end_state"]["goal_constraint"] = goal;
  return j;
}

Json Item(const std::string& command, const Json& reference) {
  return {{"domain", "search_rescue"}, {"command", command}, {"reference", reference}};
}

// Direct prompting: one request per translation, then the repairs (2 by default).
TEST(EvalService, EachVerdictFromTheMockEndpoint) {
  MockLlmServer m;
  // 0: the same goal written otherwise (the bare automaton name, the location variable).
  m.Then(MockReply::Chat(Rescue("robot1l[i+1]==rescuedPerson1").dump()));
  // 1: valid, same optimum (person 2 is as far), but another goal: not equivalent.
  m.Then(MockReply::Chat(Rescue("robot1[i+1]==rescuedPerson2").dump()));
  // 2: never JSON.
  for (int k = 0; k < 3; ++k) m.Then(MockReply::Chat("I would send robot 1 through door 1."));
  // 3: JSON that never loads (an unknown location, three times).
  for (int k = 0; k < 3; ++k) m.Then(MockReply::Chat(Rescue("robot1[i+1]==rescuedPerson9").dump()));
  EvalServer s({{"CTB_LLM_BASE_URL", m.BaseUrl()}, {"CTB_LLM_MODEL", "mock"}});
  auto c = s.Client();
  Json body = {{"prompting", "direct"},
               {"suite", {Item("Robot 1 rescues person 1.", Json::parse(kRescue1)),
                          Item("Robot 1 rescues person 1 fast.", Json::parse(kRescue1)),
                          Item("Rescue someone.", Json::parse(kRescue1)),
                          Item("Robot 1 rescues person 9.", Json::parse(kRescue1))}}};
  auto r = c.Post("/eval", body.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  Json a = Json::parse(r->body);
  ASSERT_EQ(a["items"].size(), 4u) << r->body;
  EXPECT_EQ(a["items"][0]["verdict"], "equivalent") << a["items"][0];
  EXPECT_EQ(a["items"][0]["solvable"], true);
  EXPECT_EQ(a["items"][1]["verdict"], "not_equivalent") << a["items"][1];
  EXPECT_EQ(a["items"][1]["valid"], true);
  EXPECT_EQ(a["items"][1]["solvable"], true);
  EXPECT_NE(a["items"][1].value("why", "").find("not a plan for the reference"), std::string::npos) << a["items"][1];
  EXPECT_EQ(a["items"][2]["verdict"], "unparsed") << a["items"][2];
  EXPECT_EQ(a["items"][2]["parsed"], false);
  EXPECT_EQ(a["items"][3]["verdict"], "invalid") << a["items"][3];
  EXPECT_EQ(a["items"][3]["parsed"], true);
  EXPECT_EQ(a["items"][3]["valid"], false);
  EXPECT_EQ(a["totals"], Json::parse(R"({"items": 4, "equivalent": 1, "not_equivalent": 1,
                                         "unparsed": 1, "invalid": 1, "unknown": 0})"));
  for (const auto& line : a["items"])
    for (const char* k : {"item", "domain", "parsed", "valid", "solvable", "verdict", "ms", "tokens"})
      EXPECT_TRUE(line.contains(k)) << k << " in " << line;
  EXPECT_EQ(m.Requests().size(), 8u);
}

// With a time limit too short for the check of one plan against the other state plan (the
// first-plan engine proves both optima at once, but the check needs the solver), the verdict is
// unknown, never equivalent.
TEST(EvalService, ACutOffCheckIsUnknown) {
  MockLlmServer m;
  m.Then(MockReply::Chat(Rescue("robot1l[i+1]==rescuedPerson1").dump()));
  EvalServer s({{"CTB_LLM_BASE_URL", m.BaseUrl()}, {"CTB_LLM_MODEL", "mock"}});
  auto c = s.Client();
  Json body = {{"prompting", "direct"}, {"time_limit_ms", 1},
               {"suite", {Item("Robot 1 rescues person 1.", Json::parse(kRescue1))}}};
  auto r = c.Post("/eval", body.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  Json a = Json::parse(r->body);
  EXPECT_EQ(a["items"][0]["verdict"], "unknown") << r->body;
  EXPECT_EQ(a["totals"]["equivalent"], 0);
}

TEST(EvalService, TheStreamSendsEachItemThenDone) {
  MockLlmServer m;
  m.Then(MockReply::Chat(Rescue("robot1l[i+1]==rescuedPerson1").dump()));
  EvalServer s({{"CTB_LLM_BASE_URL", m.BaseUrl()}, {"CTB_LLM_MODEL", "mock"}});
  auto c = s.Client();
  Json body = {{"prompting", "direct"}, {"stream", true},
               {"suite", {Item("Robot 1 rescues person 1.", Json::parse(kRescue1))}}};
  auto r = c.Post("/eval", body.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const auto item = r->body.find("event: item\n");
  const auto done = r->body.find("event: done\n");
  ASSERT_NE(item, std::string::npos) << r->body;
  ASSERT_NE(done, std::string::npos) << r->body;
  EXPECT_LT(item, done);
  EXPECT_NE(r->body.find("\"verdict\":\"equivalent\""), std::string::npos) << r->body;
}

TEST(EvalService, AWrongSuiteIsRefusedAtItsPointerBeforeAnyLlmCall) {
  MockLlmServer m;
  EvalServer s({{"CTB_LLM_BASE_URL", m.BaseUrl()}, {"CTB_LLM_MODEL", "mock"}});
  auto c = s.Client();
  Json bad_ref = Json::parse(kRescue1);
  bad_ref["end_state"]["goal_constraint"] = "robot1[i+1]==rescuedPersn1";
  Json body = {{"suite", {Item("ok", Json::parse(kRescue1)), Item("bad", bad_ref),
                          {{"domain", "nowhere"}, {"command", "x"}, {"reference", bad_ref}}}}};
  auto r = c.Post("/eval", body.dump(), "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400) << r->body;
  EXPECT_NE(r->body.find("/suite/1/reference/end_state/goal_constraint"), std::string::npos) << r->body;
  EXPECT_NE(r->body.find("/suite/2/domain"), std::string::npos) << r->body;
  EXPECT_TRUE(m.Requests().empty());
  auto empty = c.Post("/eval", Json({{"suite", Json::array()}}).dump(), "application/json");
  EXPECT_EQ(empty->status, 400);
}

}  // namespace
}  // namespace ctb
