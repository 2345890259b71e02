// A domain nobody wrote examples for (config/templates/drones.json, a template): the prompt is
// built from the domain itself, the shipped domains' examples come each under a label naming
// their domain, and a command goes to a verified plan (mock endpoint, real minizinc).
#include <gtest/gtest.h>

#include "../planner/test_util.h"
#include "mock_llm.h"
#include "planner/solve/solve.h"
#include "translator/pipeline.h"

namespace ctb {
// A namespace of its own: the test executable's unity build puts files with same-named
// helpers side by side.
namespace new_domain_test {
namespace {

using testing::MockLlmServer;
using testing::MockReply;

const char* kCommand =
    "The drones are in the hangar and the hangar door is closed. Drone 1 should reach A and drone "
    "2 should reach B, as fast as possible.";

const char* kReasoning =
    "Initial State\nDrone 1: in the hangar (inHangar)\nDrone 2: in the hangar (inHangar)\nHangar "
    "door: closed\n\nEnd State\nDrone 1 at A (atA) and drone 2 at B (atB), as fast as "
    "possible.\n\nEpisodes\nNone.\n\nTemporal Constraints\nNone.";

const char* kStatePlan = R"J({
  "initial_state": {"drone1": "inHangar", "drone2": "inHangar", "hangarDoor": "closed"},
  "end_state": {"maintenance_constraint": "true",
                "goal_constraint": "drone1l[i+1]==atA /\\ drone2l[i+1]==atB"},
  "constraints": {"episodes": {}, "temporal": {}, "event": {}},
  "objective": "makespan"
})J";

Domain Drones() {
  Diagnostics d;
  auto dom = LoadDomainFile(testing::ConfigDir() + "/templates/drones.json", d);
  EXPECT_TRUE(dom) << testing::AllErrors(d);
  return dom ? *dom : Domain{};
}

LlmConfig Config(const MockLlmServer& m) {
  LlmConfig c;
  c.base_url = m.BaseUrl();
  c.api_key = "sk-test";
  c.model = "mock-model";
  c.timeout_ms = 3000;
  return c;
}

// Names that belong to the shipped domains, by domain.
const std::map<std::string, std::vector<std::string>>& ShippedNames() {
  static const std::map<std::string, std::vector<std::string>> names = {
      {"assembly", {"arm1", "blockA", "onB", "onFloor"}},
      {"presentation", {"compOff", "projOn", "projl", "disconnected"}},
      {"search_rescue", {"robot1", "door1", "rescuedPerson1", "outside"}},
  };
  return names;
}

TEST(NewDomain, CommandToVerifiedPlanWithAPromptBuiltFromTheDomain) {
  Domain d = Drones();
  ASSERT_EQ(d.name, "drones");
  ASSERT_EQ(d.automata.size(), 3u);
  MockLlmServer m;
  m.Then(MockReply::Chat(kReasoning));
  m.Then(MockReply::Chat(std::string("```json\n") + kStatePlan + "\n```"));
  auto client = MakeHttpClient(Config(m));
  TranslateOptions o;
  o.prompts_dir = testing::SourceDir() + "/prompts";
  auto r = Translate(d, kCommand, *client, o);
  ASSERT_TRUE(std::holds_alternative<TranslateResult>(r)) << std::get<Error>(r).ToString();
  const TranslateResult& t = std::get<TranslateResult>(r);

  // The prompt: the domain's own names, durations and description before the command.
  auto reqs = m.Requests();
  ASSERT_EQ(reqs.size(), 2u);
  std::string system = reqs[0].body["messages"][0]["content"];
  for (const char* part : {"Action model \"drones\": 2 drones that take off in 5 s",
                           "drone1 (location variable drone1l, command variable drone1u)",
                           "drone2 (location variable drone2l", "hangarDoor", "takeOff",
                           "flyToB", "takingOff -> airborne after 5 s",
                           "flyingToA -> atA after 20 s", "opening -> open after 3 s"})
    EXPECT_NE(system.find(part), std::string::npos) << part;
  // Every example of another domain comes after a label naming that domain, and none of its
  // names appears anywhere else: not in the description, not under another domain's label.
  const std::string label = "Example from another domain, \"";
  std::vector<std::size_t> at;
  for (std::size_t p = system.find(label); p != std::string::npos; p = system.find(label, p + 1))
    at.push_back(p);
  ASSERT_EQ(at.size(), ShippedNames().size()) << system;
  for (std::size_t k = 0; k <= at.size(); ++k) {
    std::size_t begin = k == 0 ? 0 : at[k - 1];
    std::size_t end = k == at.size() ? system.size() : at[k];
    std::string segment = system.substr(begin, end - begin);
    std::string owner;
    if (k > 0) {
      std::size_t q = begin + label.size();
      owner = system.substr(q, system.find('"', q) - q);
    }
    for (const auto& [domain, names] : ShippedNames())
      for (const auto& name : names) {
        bool present = segment.find(name) != std::string::npos;
        if (domain == owner)
          EXPECT_TRUE(present) << name << " missing under the label of " << domain;
        else
          EXPECT_FALSE(present) << name << " of " << domain << " appears in segment " << k
                                << (owner.empty() ? " (the description)" : " (under " + owner + ")");
      }
  }
  EXPECT_NE(system.find("\"drones\" has no examples of its own"), std::string::npos);
  // The command comes after the description, in the user turn.
  EXPECT_NE(reqs[0].body["messages"][1]["content"].get<std::string>().find(kCommand),
            std::string::npos);

  // The state plan solves to a verified plan: the door opens (3 s), both take off (5 s), fly (20 s).
  Diagnostics diags;
  auto sp = LoadStatePlan(t.state_plan, d, diags);
  ASSERT_TRUE(sp) << testing::AllErrors(diags);
  SolveOptions so;
  so.time_limit_ms = 60000;
  auto solved = SolveDocument(d, *sp, so);
  ASSERT_TRUE(std::holds_alternative<Json>(solved)) << std::get<Error>(solved).ToString();
  const Json& traj = std::get<Json>(solved);
  EXPECT_EQ(traj["status"], "optimal");
  EXPECT_EQ(traj["verified"], true);
  EXPECT_EQ(traj["objective"]["value"], 28);
}

TEST(NewDomain, AShippedDomainKeepsItsOwnExamplesUnlabelled) {
  std::string ex = PromptExamples(testing::ShippedDomain("presentation"),
                                  testing::SourceDir() + "/prompts", Prompting::kCot);
  EXPECT_EQ(ex.find("Example from another domain"), std::string::npos);
  EXPECT_NE(ex.find("projOn"), std::string::npos);
  EXPECT_EQ(ex.find("robot1"), std::string::npos);
}

}  // namespace
}  // namespace new_domain_test
}  // namespace ctb
