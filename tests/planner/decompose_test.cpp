#include "planner/solve/decompose.h"

#include <gtest/gtest.h>

#include "planner/solve/solve.h"
#include "test_util.h"

namespace ctb {
namespace {

struct Problem {
  Domain domain;
  StatePlan plan;
};

Problem LoadData(const std::string& domain_file, const std::string& plan_file) {
  Diagnostics d;
  auto dom = LoadDomainFile(testing::SourceDir() + "/tests/data/" + domain_file, d);
  EXPECT_TRUE(dom) << testing::AllErrors(d);
  auto j = ReadJsonFile(testing::SourceDir() + "/tests/data/" + plan_file, d);
  auto sp = LoadStatePlan(*j, *dom, d);
  EXPECT_TRUE(sp) << testing::AllErrors(d);
  return {*dom, *sp};
}

TEST(SplitProblem, LinkedAutomataStayTogether) {
  const Domain& d = testing::ShippedDomain("presentation");
  Diagnostics diags;
  auto j = ReadJsonFile(testing::ConfigDir() + "/examples/presentation/test1_cot.json", diags);
  EXPECT_LT(SplitProblem(d, *LoadStatePlan(*j, d, diags)).size(), 2u);
  const Domain& sr = testing::ShippedDomain("search_rescue");  // the doors couple the robots
  auto j2 = ReadJsonFile(testing::ConfigDir() + "/examples/search_rescue/incontext.json", diags);
  EXPECT_LT(SplitProblem(sr, *LoadStatePlan(*j2, sr, diags)).size(), 2u);
}

TEST(SplitProblem, CopiesSplitWithTheirConstraints) {
  Problem p = LoadData("presentation_x2.json", "presentation_x2_plan.json");
  auto parts = SplitProblem(p.domain, p.plan);
  ASSERT_EQ(parts.size(), 2u);
  for (const auto& part : parts) {
    EXPECT_EQ(part.automata.size(), 3u);
    EXPECT_EQ(part.plan.episodes.size(), 1u);
    EXPECT_EQ(part.plan.temporals.size(), 2u);
    EXPECT_EQ(part.episode_map.size(), 1u);
  }
  EXPECT_EQ(parts[0].automata, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(parts[1].plan.goal.text,
            "comp2l[i+1]==compOff /\\ conn2l[i+1]==disconnected /\\ proj2l[i+1]==projOff");
}

TEST(SplitProblem, AChangeGoalIsNotSplit) {
  Problem p = LoadData("presentation_x2.json", "presentation_x2_plan.json");
  Diagnostics d;
  Scope scope{&p.domain, {}, {}};
  p.plan.goal.text = "comp1l[i]==compOn /\\ proj2l[i+1]==projOn";
  p.plan.goal.info = ExprInfo{};
  p.plan.goal.expr = *ParseChecked(p.plan.goal.text, scope, ExprContext::kCondition, "", d,
                                   &p.plan.goal.info);
  EXPECT_LT(SplitProblem(p.domain, p.plan).size(), 2u);
}

TEST(SolveParts, IdenticalCopiesAreSolvedOnceAndMerged) {
  Problem p = LoadData("presentation_x2.json", "presentation_x2_plan.json");
  SolveOptions o;
  o.objective = Objective::kMakespan;
  o.time_limit_ms = 120000;
  auto r = SolveDocument(p.domain, p.plan, o);
  ASSERT_TRUE(std::holds_alternative<Json>(r)) << std::get<Error>(r).ToString();
  const Json& t = std::get<Json>(r);
  EXPECT_EQ(t["status"], "optimal");
  EXPECT_EQ(t["verified"], true);
  EXPECT_EQ(t["goal_reached_at"], 2430);
  EXPECT_EQ(t["cost"], 14);
  EXPECT_EQ(t["stats"]["parts"], 2);
  EXPECT_EQ(t["stats"]["parts_reused"], 1);
  // Both copies act at the same times, so they share events: as many as one copy needs.
  EXPECT_LE(t["events"].size(), 10u);
  EXPECT_EQ(t["episodes"]["ProjectorOnDuration1"]["start"], 30);
  EXPECT_EQ(t["episodes"]["ProjectorOnDuration2"]["start"], 30);
}

TEST(SolveParts, AMergeThatFailsVerificationFallsBackToOneModel) {
  // Copy 2 only has to reach warm-up; alone it stops there, with the automatic warm-up -> on
  // transition pending, which the merged plan (still running copy 1) cannot allow.
  Problem p = LoadData("presentation_x2.json", "presentation_x2_pending_plan.json");
  SolveOptions o;
  o.time_limit_ms = 60000;
  auto r = SolveDocument(p.domain, p.plan, o);
  ASSERT_TRUE(std::holds_alternative<Json>(r)) << std::get<Error>(r).ToString();
  const Json& t = std::get<Json>(r);
  EXPECT_NE(t["stats"]["merge"].get<std::string>().find("failed verification"), std::string::npos);
  EXPECT_TRUE(t["status"] == "optimal" || t["status"] == "feasible") << t["status"];
  EXPECT_EQ(t["verified"], true);
  EXPECT_EQ(t["timelines"]["proj2"].back()["location"], "projWarmUp");
}

}  // namespace
}  // namespace ctb
