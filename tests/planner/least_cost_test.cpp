// The makespan bound of plans of least cost (cost_then_makespan, BoundOptions::least_cost_makespan,
// analyze/assignment_cost.h ReachWithinBudget): worked by hand on a cheap slow way against a dear
// fast one, and against the exact engine alone (no bound to stop at) on the cost teams of
// bench/families.py and on random teams. A bound above the lexicographic optimum would make the
// planner call a worse plan optimal: the comparisons fail loudly.
#include <gtest/gtest.h>

#include <cmath>
#include <tuple>
#include <variant>

#include "planner/analyze/bounds.h"
#include "planner/solve/solve.h"
#include "exact_engine.h"
#include "random_teams.h"
#include "team_problem.h"
#include "test_util.h"

namespace ctb {
namespace least_cost_test {
namespace {

struct Lex {
  long cost = 0, makespan = 0;
};

// An answer's cost_then_makespan value, the makespan in ticks.
Lex LexOf(const Json& value, const Domain& d) {
  return {value["cost"].get<long>(), std::lround(value["makespan"].get<double>() / d.time_resolution)};
}

// The exact engine's optimum, in ticks.
Lex ExactOptimum(const Domain& d, const StatePlan& sp, int max_horizon) {
  auto r = SolveDocument(d, sp, testing::ExactEngineAlone(Objective::kCostThenMakespan, max_horizon));
  EXPECT_TRUE(std::holds_alternative<Json>(r)) << std::get<Error>(r).ToString();
  if (!std::holds_alternative<Json>(r)) return {};
  const Json& x = std::get<Json>(r);
  EXPECT_EQ(x["status"], "optimal") << x.dump();
  if (x["status"] != "optimal") return {};
  return LexOf(x["objective"]["value"], d);
}

void ExpectNotAbove(const ObjectiveBounds& b, const Lex& optimum, const std::string& what) {
  EXPECT_LE(b.cost, optimum.cost) << what << ": THE COST BOUND IS ABOVE THE OPTIMUM";
  if (b.cost == optimum.cost)
    EXPECT_LE(b.makespan_ticks, optimum.makespan)
        << what << ": THE LEAST-COST MAKESPAN BOUND " << b.makespan_ticks
        << " IS ABOVE THE OPTIMUM " << optimum.makespan;
}

constexpr BoundOptions kOn{.least_cost_makespan = true};

// One robot, two ways to the goal: 10 s + 10 s at cost 1 each, or 1 s + 1 s at cost 5 each. The
// least cost is 2, and every plan of that cost takes 20 s; the fast way's 2 s bounds only
// makespan.
TEST(LeastCostMakespan, ACheapSlowWayAgainstADearFastOne) {
  Diagnostics diags;
  auto d = LoadDomain(testing::MustParse(R"({"name": "ways", "automata": [{"name": "r",
    "locations": ["start", "slow", "fast", "goal"], "commands": ["walk", "run"], "transitions": [
      {"from": "start", "to": "slow", "guard": "ru[i]==walk", "cost": 1},
      {"from": "slow", "to": "goal", "duration": [10, 10], "cost": 1},
      {"from": "start", "to": "fast", "guard": "ru[i]==run", "cost": 5},
      {"from": "fast", "to": "goal", "duration": [1, 1], "cost": 5}]}]})"), diags);
  ASSERT_TRUE(d) << testing::AllErrors(diags);
  auto sp = LoadStatePlan(testing::MustParse(R"({"initial_state": {"r": "start"},
    "end_state": {"maintenance_constraint": "true", "goal_constraint": "rl[i+1]==goal"}})"),
                          *d, diags);
  ASSERT_TRUE(sp) << testing::AllErrors(diags);
  const ObjectiveBounds off = LowerBounds(*d, *sp);
  const ObjectiveBounds on = LowerBounds(*d, *sp, kOn);
  EXPECT_EQ(off.cost, 2);
  EXPECT_EQ(off.makespan_ticks, 1);  // the fast way's second move
  EXPECT_EQ(on.cost, 2);
  EXPECT_EQ(on.makespan_ticks, 10);  // the slow way's
  const Lex optimum = ExactOptimum(*d, *sp, 4);
  EXPECT_EQ(optimum.cost, 2);
  EXPECT_EQ(optimum.makespan, 10);
  // The solve proves it at once: the first plan meets the bound.
  SolveOptions o;
  o.objective = Objective::kCostThenMakespan;
  auto r = SolveDocument(*d, *sp, o);
  ASSERT_TRUE(std::holds_alternative<Json>(r));
  EXPECT_EQ(std::get<Json>(r)["status"], "optimal");
  EXPECT_EQ(std::get<Json>(r)["stats"]["proved_by"], "lower bound");
}

// Two persons, three robots: A cheap (1) and slow (10 s), B and C dear (3) and fast (1 s). Each
// robot alone may serve either person within the least cost (4: A and one of B, C), so no location
// is cut; but every assignment within that cost has A serve someone: the least-cost makespan is
// A's 10 s (ReachWithinBudget's bottleneck), where the unconditional bound is 1 s.
TEST(LeastCostMakespan, EveryCheapEnoughAssignmentWaitsForTheSlowRobot) {
  Json automata = Json::array();
  for (auto [name, cost, time] : {std::tuple{"a", 1, 10}, std::tuple{"b", 3, 1}, std::tuple{"c", 3, 1}}) {
    const std::string n = name;
    Json ts = Json::array();
    for (int p : {1, 2})
      ts.push_back({{"from", "start"}, {"to", "p" + std::to_string(p)},
                    {"guard", n + "u[i]==go" + std::to_string(p)}, {"cost", cost},
                    {"duration", {time, time}}});
    automata.push_back({{"name", n}, {"locations", {"start", "p1", "p2"}},
                        {"commands", {"go1", "go2"}}, {"transitions", ts}});
  }
  Diagnostics diags;
  auto d = LoadDomain(Json{{"name", "team"}, {"automata", automata}}, diags);
  ASSERT_TRUE(d) << testing::AllErrors(diags);
  auto sp = LoadStatePlan(testing::MustParse(R"json({"initial_state": {"a": "start", "b": "start",
    "c": "start"}, "end_state": {"maintenance_constraint": "true", "goal_constraint":
    "(al[i+1]==p1 \\/ bl[i+1]==p1 \\/ cl[i+1]==p1) /\\ (al[i+1]==p2 \\/ bl[i+1]==p2 \\/ cl[i+1]==p2)"}})json"),
                          *d, diags);
  ASSERT_TRUE(sp) << testing::AllErrors(diags);
  const ObjectiveBounds on = LowerBounds(*d, *sp, kOn);
  EXPECT_EQ(on.cost, 4);
  EXPECT_EQ(on.makespan_ticks, 10);
  EXPECT_EQ(LowerBounds(*d, *sp).makespan_ticks, 1);
  const Lex optimum = ExactOptimum(*d, *sp, 6);
  EXPECT_EQ(optimum.cost, 4);
  EXPECT_EQ(optimum.makespan, 10);
}

// bench/families.py's cost teams (who rescues whom is free; the cheap robots are slow): the bound
// is the exact optimum (2 robots and 2 persons; 3 robots take the exact engine about a minute).
TEST(LeastCostMakespan, IsTheOptimumOfASmallCostTeam) {
  for (auto [robots, persons] : {std::pair{2, 2}}) {
    testing::TeamProblem p = testing::CostTeam(robots, persons);
    const ObjectiveBounds on = LowerBounds(p.domain, p.plan, kOn);
    const ObjectiveBounds off = LowerBounds(p.domain, p.plan);
    const Lex optimum = ExactOptimum(p.domain, p.plan, 12);
    const std::string what = std::to_string(robots) + " robots, " + std::to_string(persons) + " persons";
    ExpectNotAbove(on, optimum, what);
    EXPECT_EQ(on.cost, optimum.cost) << what;
    EXPECT_EQ(on.makespan_ticks, optimum.makespan) << what;
    EXPECT_LT(off.makespan_ticks, on.makespan_ticks) << what;
  }
}

// The `cost_spare` team of 4 robots for 3 persons: the least cost, 37, has robot 3 (cheapest, three
// times slower) open door 2 and rescue person 3: 30 s to the door, 1 s for it to open, 6 s to the
// person, so every plan of that cost ends at 37 s. The first cut removes the routes too dear to
// take, but the bottleneck still read the arrival times of the whole model (robot 3 through door 1
// in 31 s): 35. Run again on the cut model, the rule reads its arrival times: 37, and the solve
// proves the plan at once (it was `feasible` at 10 s).
TEST(LeastCostMakespan, TheCutModelIsReadAgain) {
  testing::TeamProblem p = testing::CostTeam(4, 3);
  BoundOptions once = kOn;
  once.least_cost_cuts = 100;  // past the rule's depth: one cut only, the model as read before
  const ObjectiveBounds again = LowerBounds(p.domain, p.plan, kOn);
  const ObjectiveBounds first = LowerBounds(p.domain, p.plan, once);
  EXPECT_EQ(again.cost, 37);
  EXPECT_EQ(first.makespan_ticks, 35);
  EXPECT_EQ(again.makespan_ticks, 37);
  SolveOptions o;
  o.objective = Objective::kCostThenMakespan;
  o.time_limit_ms = 60000;
  auto r = SolveDocument(p.domain, p.plan, o);
  ASSERT_TRUE(std::holds_alternative<Json>(r));
  const Json& x = std::get<Json>(r);
  EXPECT_EQ(x["status"], "optimal") << x["stats"].dump();
  const Lex value = LexOf(x["objective"]["value"], p.domain);
  EXPECT_EQ(value.cost, 37);
  EXPECT_EQ(value.makespan, 37);
}

// Random teams (random_teams.h): never above the exact lexicographic optimum.
TEST(LeastCostMakespan, NeverAboveTheExactOptimumOfRandomTeams) {
  int compared = 0, bites = 0;
  for (unsigned seed = 9100; seed < 9106; ++seed) {
    testing::TeamProblemGenerator gen(seed);
    testing::RandomProblem p = gen.Next();
    Diagnostics diags;
    auto d = LoadDomain(p.domain, diags);
    ASSERT_TRUE(d) << testing::AllErrors(diags) << p.Describe();
    auto sp = LoadStatePlan(p.state_plan, *d, diags);
    ASSERT_TRUE(sp) << testing::AllErrors(diags) << p.Describe();
    auto r = SolveDocument(*d, *sp, testing::ExactEngineAlone(Objective::kCostThenMakespan));
    ASSERT_TRUE(std::holds_alternative<Json>(r)) << std::get<Error>(r).ToString();
    const Json& x = std::get<Json>(r);
    if (x["status"] != "optimal") continue;
    const Lex optimum = LexOf(x["objective"]["value"], *d);
    const ObjectiveBounds on = LowerBounds(*d, *sp, kOn);
    ExpectNotAbove(on, optimum, "seed " + std::to_string(seed) + "\n" + p.Describe());
    bites += on.makespan_ticks > LowerBounds(*d, *sp).makespan_ticks;
    ++compared;
  }
  std::cout << compared << " compared, the least-cost makespan bound rose on " << bites << "\n";
  EXPECT_GE(compared, 4);
  EXPECT_GE(bites, 1) << "the bound never rose: the test compares nothing new";
}

}  // namespace
}  // namespace least_cost_test
}  // namespace ctb
