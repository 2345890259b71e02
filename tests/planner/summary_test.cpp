// The plain-language restatement of state plans (issue 10, part 1).
#include "planner/explain/summary.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "test_util.h"

namespace ctb {
namespace {

struct Example {
  std::string domain, path;
};

// Every shipped state plan: the thesis' examples and the test data (with their domains).
std::vector<Example> ShippedExamples() {
  std::vector<Example> out;
  for (const auto& dir : std::filesystem::directory_iterator(testing::ConfigDir() + "/examples"))
    for (const auto& f : std::filesystem::directory_iterator(dir.path()))
      out.push_back({dir.path().filename().string(), f.path().string()});
  out.push_back({"presentation", testing::SourceDir() + "/tests/data/deadline_infeasible.json"});
  for (const char* f : {"deadline_boot", "change_not_allowed", "overlap", "maintenance_blocks",
                        "three_together"})
    out.push_back({"presentation", testing::SourceDir() + "/tests/data/explain/" + f + ".json"});
  out.push_back({"search_rescue", testing::SourceDir() + "/tests/data/explain/unreachable.json"});
  std::sort(out.begin(), out.end(), [](auto& a, auto& b) { return a.path < b.path; });
  return out;
}

std::string TextAt(const Json& summary, const std::string& pointer) {
  for (const auto& s : summary)
    if (s["pointer"] == pointer) return s["text"];
  return "";
}

TEST(Summary, EveryShippedExampleHasEveryPartWithEveryBound) {
  auto examples = ShippedExamples();
  ASSERT_GE(examples.size(), 15u);
  for (const auto& ex : examples) {
    SCOPED_TRACE(ex.path);
    const Domain& d = testing::ShippedDomain(ex.domain);
    StatePlan sp = testing::ShippedStatePlan(ex.domain, ex.path);
    Json s = SummarizeStatePlan(d, sp);
    std::set<std::string> want{"/initial_state", "/end_state/goal_constraint"};
    if (sp.maintenance.expr.op != Expr::Op::kTrue) want.insert("/end_state/maintenance_constraint");
    for (const auto& e : sp.episodes) want.insert("/constraints/episodes/" + e.name);
    for (const auto& t : sp.temporals) want.insert("/constraints/temporal/" + t.name);
    for (const SharedEvent* e : sp.AllSharedEvents()) want.insert("/constraints/event/" + e->name);
    for (const auto& o : sp.orders)
      if (!o.name.empty()) want.insert("/constraints/temporal/" + o.name);
    if (!sp.sequence.empty()) want.insert("/constraints/sequence");
    if (!sp.forbidden.empty()) want.insert("/constraints/forbidden");
    std::set<std::string> got;
    for (const auto& x : s) {
      EXPECT_TRUE(got.insert(x["pointer"].get<std::string>()).second) << "one sentence per part";
      std::string text = x["text"];
      EXPECT_FALSE(text.empty());
      EXPECT_EQ(text.back(), '.') << text;
    }
    EXPECT_EQ(got, want);
    // Every bound is stated with its number; every initial location is named.
    for (const auto& e : sp.episodes) {
      std::string t = TextAt(s, "/constraints/episodes/" + e.name);
      EXPECT_NE(t.find(SecondsText(e.lower) + " "), std::string::npos) << t;
      EXPECT_NE(t.find(SecondsText(e.upper) + " s"), std::string::npos) << t;
    }
    for (const auto& tc : sp.temporals) {
      std::string t = TextAt(s, "/constraints/temporal/" + tc.name);
      EXPECT_NE(t.find(SecondsText(tc.lower) + " "), std::string::npos) << t;
      EXPECT_NE(t.find(SecondsText(tc.upper) + " s"), std::string::npos) << t;
      EXPECT_NE(t.find(tc.name), std::string::npos) << t;
    }
    std::string init = TextAt(s, "/initial_state");
    for (std::size_t a = 0; a < d.automata.size(); ++a)
      EXPECT_NE(init.find(d.automata[a].name + " is " + d.automata[a].locations[sp.initial[a]]),
                std::string::npos) << init;
    // Deterministic.
    EXPECT_EQ(SummarizeStatePlan(d, sp), s);
  }
}

TEST(Summary, TestPrompt1Wording) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = testing::ShippedStatePlan("presentation", testing::ConfigDir() + "/examples/presentation/test1_cot.json");
  Json s = SummarizeStatePlan(d, sp);
  EXPECT_EQ(TextAt(s, "/constraints/temporal/ProjectorOnWithin60"),
            "Within 0 to 60 s after proj goes from projOff to projWarmUp, proj is projOn "
            "(temporal constraint ProjectorOnWithin60).");
  // The self-reference that orders the events is not read out: "after" says it.
  EXPECT_EQ(TextAt(s, "/constraints/temporal/ShutdownWithin600"),
            "Exactly 600 s after proj goes from projOn to projConfirm, proj is projOff, conn is "
            "disconnected and comp is compOff (temporal constraint ShutdownWithin600).");
  EXPECT_EQ(TextAt(s, "/constraints/episodes/ProjectorOnDuration"),
            "Episode ProjectorOnDuration starts the first time proj is projOn; while it lasts, "
            "proj is projOn; it lasts exactly 1800 s.");
  EXPECT_EQ(TextAt(s, "/end_state/goal_constraint"),
            "At the end, comp is compOff, conn is disconnected and proj is projOff.");
  EXPECT_NE(TextAt(s, "/initial_state").find(d.description), std::string::npos)
      << "the domain's description is used";
}

TEST(Summary, BoundsAreWordedApart) {
  EXPECT_EQ(BoundWords(600, 600), "exactly 600 s");
  EXPECT_EQ(BoundWords(0, 60), "within 0 to 60 s");
  EXPECT_EQ(BoundWords(30, 60), "between 30 and 60 s");
  EXPECT_EQ(BoundWords(30, 1e7), "at least 30 s (at most 10000000 s, the largest bound)");
  EXPECT_EQ(BoundWords(0.5, 0.5), "exactly 0.5 s");
}

TEST(Summary, MaintenanceSharedEventsAndConnectives) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = testing::ShippedStatePlan("presentation", testing::SourceDir() + "/tests/data/explain/overlap.json");
  Json s = SummarizeStatePlan(d, sp);
  EXPECT_EQ(TextAt(s, "/constraints/event/TogetherFromTheStart"),
            "These happen at one and the same moment: the start of episode ProjectorOn and the "
            "start of episode ProjectorDark.");
  StatePlan m = testing::ShippedStatePlan("presentation", testing::SourceDir() + "/tests/data/explain/three_together.json");
  Json t = SummarizeStatePlan(d, m);
  EXPECT_EQ(TextAt(t, "/end_state/maintenance_constraint"),
            "Until the end, at every moment: if conn is connected, then comp is compOff.");
  EXPECT_EQ(TextAt(t, "/end_state/goal_constraint"),
            "There is no goal state: the plan ends once every constraint is met.");
  Json j = testing::MustParse(R"({"initial_state": {"comp": "compOff", "conn": "disconnected",
      "proj": "projOff"}, "end_state": {"goal_constraint":
      "not (projl[i+1]==projOn \\/ compl[i+1]!=compOff) /\\ proju[i+1]==projTurnOn"}})");
  Diagnostics diags;
  auto sp2 = LoadStatePlan(j, d, diags);
  ASSERT_TRUE(sp2) << testing::AllErrors(diags);
  EXPECT_EQ(TextAt(SummarizeStatePlan(d, *sp2), "/end_state/goal_constraint"),
            "At the end, it is not the case that (either proj is projOn or comp is not compOff) "
            "and proj is given the command projTurnOn.");
}

TEST(Summary, QuantifiersAreSaidAsWrittenAndTeamsOnce) {
  Diagnostics diags;
  auto t = ReadJsonFile(testing::ConfigDir() + "/templates/search_rescue_team.json", diags);
  ASSERT_TRUE(t) << testing::AllErrors(diags);
  ExpandOptions o;
  o.parameters["N"] = 3;
  auto d = LoadDomain(*t, diags, o);
  ASSERT_TRUE(d) << testing::AllErrors(diags);
  Json j = testing::MustParse(R"J({"initial_state": {"robot1": "outside", "robot2": "outside",
      "robot3": "outside", "door1": "closed", "door2": "closed", "door3": "open"},
      "end_state": {"goal_constraint": "every(k in robot: robot{k}l[i+1]==rescuedPerson{k})",
                    "maintenance_constraint": "every(p in 1..2: any(k in robot: robot{k}u[i]!=goToPerson{p}))"}})J");
  auto sp = LoadStatePlan(j, *d, diags);
  ASSERT_TRUE(sp) << testing::AllErrors(diags);
  Json s = SummarizeStatePlan(*d, *sp);
  EXPECT_NE(TextAt(s, "/initial_state").find("initially every robot (robot1 to robot3) is outside, "
                                             "every door (door1 to door2) is closed and door3 is "
                                             "open."),
            std::string::npos)
      << TextAt(s, "/initial_state");
  EXPECT_EQ(TextAt(s, "/end_state/goal_constraint"),
            "At the end, for every k in robot (the 3 instances robot1 to robot3), robot{k} is "
            "rescuedPerson{k}.");
  EXPECT_EQ(TextAt(s, "/end_state/maintenance_constraint"),
            "Until the end, at every moment: for every p from 1 to 2, (for some k in robot (the 3 "
            "instances robot1 to robot3), robot{k} is not given the command goToPerson{p}).");
}

}  // namespace
}  // namespace ctb
