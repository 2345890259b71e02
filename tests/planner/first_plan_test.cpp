// The first-plan engine (planner/search, issue 18): plans on the shipped examples, and on random
// problems no plan the verifier refuses (the engine follows the verifier's rules exactly).
#include "planner/search/first_plan.h"

#include <cmath>

#include <gtest/gtest.h>

#include "planner/analyze/bounds.h"
#include "planner/verify/verify.h"
#include "random_problem.h"
#include "team_problem.h"
#include "test_util.h"

namespace ctb {
namespace {

FirstPlanResult Find(const Domain& d, const StatePlan& sp, Objective objective,
                     long limit_ms = 2000) {
  FirstPlanOptions o;
  o.objective = objective;
  o.time_limit_ms = limit_ms;
  return FindFirstPlan(d, sp, o);
}

FirstPlanResult FindExample(const std::string& domain, const std::string& file,
                            Objective objective) {
  const Domain& d = testing::ShippedDomain(domain);
  StatePlan sp = testing::ShippedStatePlan(domain, testing::ConfigDir() + "/examples/" + file);
  FirstPlanResult r = Find(d, sp, objective);
  if (r.best) {
    EXPECT_TRUE(VerifyTrajectory(*r.best, d, sp, 1).empty()) << file;
  }
  EXPECT_EQ(r.rejected, 0) << file;
  return r;
}

TEST(FirstPlan, SearchRescueRobot1RescuesPerson1At11) {
  FirstPlanResult r = FindExample("search_rescue", "search_rescue/test2.json", Objective::kMakespan);
  ASSERT_TRUE(r.best);
  EXPECT_EQ(r.makespan, 11);  // the optimum (thesis 5.3.2)
}

TEST(FirstPlan, AssemblyAToTheFloorThenBOnA) {
  FirstPlanResult r = FindExample("assembly", "assembly/test.json", Objective::kMakespan);
  ASSERT_TRUE(r.best);
  EXPECT_GE(r.makespan, 4);  // the optimum
  EXPECT_LE(r.makespan, 6);
}

TEST(FirstPlan, PresentationTestPrompt1) {
  FirstPlanResult r =
      FindExample("presentation", "presentation/test1_cot.json", Objective::kMakespan);
  ASSERT_TRUE(r.best);
  EXPECT_GE(r.makespan, 2430);  // the optimum
}

TEST(FirstPlan, EveryShippedExampleGivesOnlyVerifiedPlans) {
  for (const auto& [domain, file] :
       std::vector<std::pair<std::string, std::string>>{
           {"presentation", "presentation/incontext.json"},
           {"presentation", "presentation/test1_direct.json"},
           {"presentation", "presentation/test2_cot.json"},
           {"search_rescue", "search_rescue/incontext.json"},
           {"search_rescue", "search_rescue/test1.json"},
           {"assembly", "assembly/incontext.json"}})
    for (Objective obj : {Objective::kCost, Objective::kMakespan, Objective::kCostThenMakespan})
      FindExample(domain, file, obj);
}

// The thesis' direct prompt starts its "within 60 s" at `projl[0]==projOff`, a fixed stage. Stage 0
// is the initial state in every run, so the engine reads it there; its plan meets the lower bound
// (the optimum, cost 7, as with the chain-of-thought prompt).
TEST(FirstPlan, TheDirectPromptReadsStageZeroAndMeetsTheBound) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = testing::ShippedStatePlan(
      "presentation", testing::ConfigDir() + "/examples/presentation/test1_direct.json");
  for (Objective obj : {Objective::kCost, Objective::kMakespan}) {
    // As the solve runs it: told the bound, the engine searches until it meets it.
    const ObjectiveBounds bound = LowerBounds(d, sp);
    FirstPlanOptions o;
    o.objective = obj;
    o.time_limit_ms = 60000;
    o.good_enough = [&](long cost, long makespan) {
      return MeetsLowerBounds(bound, obj, cost, makespan);
    };
    FirstPlanResult r = FindFirstPlan(d, sp, o);
    EXPECT_EQ(r.declined, "");
    ASSERT_TRUE(r.best);
    EXPECT_TRUE(VerifyTrajectory(*r.best, d, sp, 1).empty());
    EXPECT_TRUE(MeetsLowerBounds(bound, obj, r.cost, r.makespan))
        << "cost " << r.cost << ", makespan " << r.makespan;
  }
  EXPECT_EQ(Find(d, sp, Objective::kCost).cost, 7);
}

// Stage 0 read as false: the temporal constraint's first event never happens, so no plan.
// A later fixed stage depends on the goal event (min(n, g)) and is still declined.
TEST(FirstPlan, StageZeroIsReadAsItIsAndLaterFixedStagesAreDeclined) {
  const Domain& d = testing::ShippedDomain("presentation");
  auto load = [&](const std::string& event1) {
    Diagnostics diags;
    auto sp = LoadStatePlan(testing::MustParse(R"({
      "initial_state": {"comp": "compOff", "conn": "disconnected", "proj": "projOff"},
      "end_state": {"maintenance_constraint": "true",
                    "goal_constraint": "projl[i+1]==projOn"},
      "constraints": {"temporal": {"t": {"accepting_event1_constraint": ")" + event1 + R"(",
        "accepting_event2_constraint": "projl[i+1]==projOn", "lower_bound": 0,
        "upper_bound": 100}}}})"), d, diags);
    EXPECT_TRUE(sp) << testing::AllErrors(diags);
    return *sp;
  };
  StatePlan holds = load("projl[0]==projOff");
  FirstPlanResult r = Find(d, holds, Objective::kMakespan);
  ASSERT_TRUE(r.best);
  EXPECT_TRUE(VerifyTrajectory(*r.best, d, holds, 1).empty());
  StatePlan never = load("projl[0]==projOn");
  r = Find(d, never, Objective::kMakespan);
  EXPECT_EQ(r.declined, "");
  EXPECT_FALSE(r.best);
  StatePlan later = load("projl[1]==projOff");
  r = Find(d, later, Objective::kMakespan);
  EXPECT_NE(r.declined.find("fixed stage after 0"), std::string::npos) << r.declined;
}

// Test prompt 2: the optimum (cost 10) disconnects when the projector's episode ends, so that it
// cools down on its own, and turns the computer off 30 s (its shutdown) before the constraint's
// 600 s: the engine tries each transition its lead before a target time, and meets the bound.
TEST(FirstPlan, TestPromptTwoReachesTheOptimumByLeadTimes) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = testing::ShippedStatePlan(
      "presentation", testing::ConfigDir() + "/examples/presentation/test2_cot.json");
  FirstPlanResult r = Find(d, sp, Objective::kCost);
  ASSERT_TRUE(r.best);
  EXPECT_EQ(r.cost, 10);
  EXPECT_TRUE(MeetsLowerBounds(LowerBounds(d, sp), Objective::kCost, r.cost, r.makespan));
}

TEST(FirstPlan, DeclinesConditionsThatReadCommands) {
  const Domain& d = testing::ShippedDomain("search_rescue");
  Diagnostics diags;
  auto sp = LoadStatePlan(testing::MustParse(R"({
    "initial_state": {"robot1": "outside", "robot2": "outside", "door1": "closed",
                      "door2": "closed", "door3": "open"},
    "end_state": {"maintenance_constraint": "true",
                  "goal_constraint": "robot1u[i]==goToDoor1"}})"), d, diags);
  ASSERT_TRUE(sp) << testing::AllErrors(diags);
  FirstPlanResult r = Find(d, *sp, Objective::kCost);
  EXPECT_FALSE(r.best);
  EXPECT_NE(r.declined.find("commands"), std::string::npos) << r.declined;
}

TEST(FirstPlan, StopsWhenGoodEnough) {
  const Domain& d = testing::ShippedDomain("search_rescue");
  StatePlan sp = testing::ShippedStatePlan(
      "search_rescue", testing::ConfigDir() + "/examples/search_rescue/test2.json");
  FirstPlanOptions o;
  o.objective = Objective::kMakespan;
  int plans = 0;
  o.on_plan = [&](const Trajectory&, long, long) { ++plans; };
  o.good_enough = [](long, long makespan) { return makespan <= 1000; };
  FirstPlanResult r = FindFirstPlan(d, sp, o);
  ASSERT_TRUE(r.best);
  EXPECT_EQ(plans, 1);
  EXPECT_FALSE(r.exhausted);
}

// Which robot rescues whom is free, and robots have three speeds (bench/families.py `assign`):
// the goal is a conjunction of disjunctions. Read as clauses, one robot per person, the relaxed
// plan leads each robot to a person of its own; reading only the goal's conjunction it saw nothing
// needed and found no plan in 15 s from four robots on.
TEST(FirstPlan, FreeAssignmentWithMixedSpeeds) {
  for (int n : {4, 8}) {
    testing::TeamProblem p = testing::MixedSpeedTeam(n);
    FirstPlanOptions o;
    o.objective = Objective::kMakespan;
    o.time_limit_ms = 5000;
    o.good_enough = [](long, long makespan) { return makespan <= 30; };  // the optimum
    FirstPlanResult r = FindFirstPlan(p.domain, p.plan, o);
    ASSERT_TRUE(r.best) << n << " robots";
    EXPECT_EQ(r.makespan, 30) << n << " robots";
    EXPECT_LT(r.expanded, 1000) << n << " robots";  // guided, not blind
    EXPECT_TRUE(VerifyTrajectory(*r.best, p.domain, p.plan, 1).empty());
  }
}

// Random problems (the differential suite's generator): guards across automata, episodes,
// temporal and shared-event constraints, every objective. The engine replays the verifier's
// rules while it searches, so it must never propose a plan the verifier refuses.
// search_rescue as a template (config/templates/search_rescue_team.json) with n robots; with
// `own`, robot k's template lists only its own person k (as bench/gen_scaled.py's
// rescue_team(n, "own")): the domain grows linearly with the team.
Domain RescueTeam(int n, bool own) {
  Diagnostics d;
  auto t = ReadJsonFile(testing::ConfigDir() + "/templates/search_rescue_team.json", d);
  if (!t) {
    ADD_FAILURE() << testing::AllErrors(d);
    return {};
  }
  Json doc = *t;
  doc["parameters"]["N"] = n;
  if (own) {
    Json& robot = doc["automata"][0];
    for (const char* key : {"locations", "commands", "transitions"}) {
      Json items = Json::array();
      for (const Json& it : robot[key]) {
        if (!it.is_object() || !it.contains("for")) {
          items.push_back(it);
          continue;
        }
        std::string each = it["each"].dump();
        for (std::size_t at = each.find("{p}"); at != std::string::npos; at = each.find("{p}"))
          each.replace(at, 3, "{k}");
        Json parts = Json::parse(each);
        if (!parts.is_array()) parts = Json::array({parts});
        for (const Json& x : parts) items.push_back(x);
      }
      robot[key] = items;
    }
  }
  auto dom = LoadDomain(doc, d);
  EXPECT_TRUE(dom) << testing::AllErrors(d);
  return dom ? *dom : Domain{};
}

StatePlan TeamPlan(const Domain& dom, int n, const std::string& goal) {
  Json init = {{"door1", "closed"}, {"door2", "closed"}, {"door3", "open"}};
  for (int r = 1; r <= n; ++r) init["robot" + std::to_string(r)] = "outside";
  Json j = {{"initial_state", init}, {"end_state", {{"goal_constraint", goal}}}};
  Diagnostics d;
  auto sp = LoadStatePlan(j, dom, d);
  EXPECT_TRUE(sp) << testing::AllErrors(d);
  return sp ? *sp : StatePlan{};
}

// A goal said once with a quantifier is its written-out conjunction (disjunction): the same
// bounds, the same first plan.
TEST(FirstPlan, AQuantifiedGoalIsItsWrittenOutForm) {
  const int n = 4;
  const Domain dom = RescueTeam(n, false);
  std::string every, some;
  for (int r = 1; r <= n; ++r)
    every += (r > 1 ? " /\\ " : "") + ("robot" + std::to_string(r) + "l[i+1]==rescuedPerson" +
                                       std::to_string(r));
  for (int p = 1; p <= 2; ++p) {
    std::string any;
    for (int r = 1; r <= n; ++r)
      any += (r > 1 ? " \\/ " : "") + ("robot" + std::to_string(r) + "l[i+1]==rescuedPerson" +
                                       std::to_string(p));
    some += (p > 1 ? " /\\ " : "") + ("(" + any + ")");
  }
  const std::vector<std::pair<std::string, std::string>> pairs = {
      {"every(k in robot: robot{k}l[i+1]==rescuedPerson{k})", every},
      {"every(p in 1..2: any(k in robot: robot{k}l[i+1]==rescuedPerson{p}))", some}};
  for (const auto& [quantified, written] : pairs) {
    SCOPED_TRACE(quantified);
    const StatePlan q = TeamPlan(dom, n, quantified), w = TeamPlan(dom, n, written);
    ASSERT_TRUE(q.goal.written.has_value());
    EXPECT_FALSE(w.goal.written.has_value());
    const ObjectiveBounds bq = LowerBounds(dom, q), bw = LowerBounds(dom, w);
    EXPECT_EQ(bq.cost, bw.cost);
    EXPECT_EQ(bq.makespan_ticks, bw.makespan_ticks);
    EXPECT_EQ(bq.events, bw.events);
    for (Objective o : {Objective::kMakespan, Objective::kCost}) {
      FirstPlanResult a = Find(dom, q, o), b = Find(dom, w, o);
      ASSERT_TRUE(a.best && b.best);
      EXPECT_EQ(a.cost, b.cost);
      EXPECT_EQ(a.makespan, b.makespan);
      EXPECT_TRUE(VerifyTrajectory(*a.best, dom, w, 1).empty());  // valid for the written form
      EXPECT_TRUE(VerifyTrajectory(*b.best, dom, q, 1).empty());
    }
  }
}

// A team of 256, its goal said once (one conjunct a robot written out is over 8,192
// characters): loaded, planned and proved optimal by its lower bound.
TEST(FirstPlan, ATeamOf256IsPlannedAndProvedByItsBound) {
  const int n = 256;
  const Domain dom = RescueTeam(n, true);
  ASSERT_EQ(dom.automata.size(), 259u);
  const StatePlan sp = TeamPlan(dom, n, "every(k in robot: robot{k}l[i+1]==rescuedPerson{k})");
  FirstPlanResult r = Find(dom, sp, Objective::kMakespan, 20000);
  ASSERT_TRUE(r.best);
  EXPECT_EQ(r.makespan, 11);  // the thesis' optimum (5.3.2): every robot by door 1
  EXPECT_TRUE(MeetsLowerBounds(LowerBounds(dom, sp), Objective::kMakespan, r.cost, r.makespan));
}

TEST(FirstPlan, RandomProblemsNeverGiveAPlanTheVerifierRefuses) {
  int found = 0, ran = 0;
  for (unsigned seed = 0; seed < 200; ++seed) {
    testing::ProblemGenerator gen(seed);
    testing::RandomProblem p = gen.Next();
    Diagnostics diags;
    auto d = LoadDomain(p.domain, diags);
    auto sp = d ? LoadStatePlan(p.state_plan, *d, diags) : std::nullopt;
    ASSERT_TRUE(sp) << "seed " << seed << testing::AllErrors(diags);
    FirstPlanResult r = Find(*d, *sp, sp->objective, 200);
    EXPECT_EQ(r.rejected, 0) << "seed " << seed << "\n" << p.Describe();
    if (!r.declined.empty()) continue;
    ++ran;
    if (!r.best) continue;
    ++found;
    const long tps = std::lround(1.0 / d->time_resolution);
    auto problems = VerifyTrajectory(*r.best, *d, *sp, tps);
    EXPECT_TRUE(problems.empty()) << "seed " << seed << ": " << problems[0];
  }
  // Most random problems are feasible and small: the engine must find plans for many of them.
  EXPECT_GT(ran, 100);
  EXPECT_GT(found, ran / 3) << found << " of " << ran;
}

}  // namespace
}  // namespace ctb
