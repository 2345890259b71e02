// Lower bounds that hold for every plan (issue 9): earliest times (analyze/earliest.h), the
// delete relaxation (analyze/relaxed_cost.h), guard landmarks (analyze/bounds.h) and the work only
// helpers can do (analyze/workload.h, issue 18). Soundness on random problems is checked against
// every plan the brute-force enumeration finds and against exact optima (brute_force_test.cpp).
#include "planner/analyze/earliest.h"

#include <gtest/gtest.h>

#include <variant>

#include "planner/analyze/relaxed_cost.h"
#include "planner/analyze/workload.h"
#include "planner/analyze/bounds.h"
#include "planner/solve/solve.h"
#include "test_util.h"

namespace ctb {
namespace {

StatePlan Plan(const std::string& domain, const Json& j) {
  Diagnostics d;
  auto sp = LoadStatePlan(j, testing::ShippedDomain(domain), d);
  if (!sp) ADD_FAILURE() << testing::AllErrors(d);
  return sp ? *sp : StatePlan{};
}

StatePlan Example(const std::string& domain, const std::string& file) {
  const std::string path = testing::ConfigDir() + "/examples/" + domain + "/" + file;
  return testing::ShippedStatePlan(domain, path);
}

long Ticks(const Domain& d, double seconds) { return std::lround(seconds / d.time_resolution); }

int Loc(const Domain& d, const std::string& automaton, const std::string& loc) {
  for (const auto& a : d.automata)
    if (a.name == automaton)
      for (std::size_t l = 0; l < a.locations.size(); ++l)
        if (a.locations[l] == loc) return static_cast<int>(l);
  ADD_FAILURE() << automaton << " has no location " << loc;
  return 0;
}

int Automaton(const Domain& d, const std::string& name) {
  for (std::size_t a = 0; a < d.automata.size(); ++a)
    if (d.automata[a].name == name) return static_cast<int>(a);
  ADD_FAILURE() << "no automaton " << name;
  return 0;
}

// A robot that goes through door 1 waits for the door to open (1 s after someone starts opening
// it): the guard, not the robot's own graph, makes the 11 s of the optimal plan.
TEST(Earliest, RobotsWaitForTheDoor) {
  const Domain& d = testing::ShippedDomain("search_rescue");
  StatePlan sp = Example("search_rescue", "test1.json");
  auto e = ComputeEarliestTimes(d, sp);
  ASSERT_TRUE(e);
  const int r1 = Automaton(d, "robot1");
  EXPECT_EQ(e->arrival[r1][Loc(d, "robot1", "atDoor1")], Ticks(d, 1));
  EXPECT_EQ(e->arrival[r1][Loc(d, "robot1", "insideRoom1")], Ticks(d, 2));
  EXPECT_EQ(e->arrival[r1][Loc(d, "robot1", "rescuedPerson1")], Ticks(d, 11));
  EXPECT_EQ(e->goal, Ticks(d, 11));
  // The graph bound alone ignores the door: 10 s.
  EXPECT_EQ(LowerBounds(d, sp).makespan_ticks, Ticks(d, 11));
}

// Test prompt 1: the projector warms up (30 s), stays on for its 1800 s episode, and the shutdown
// constraint opens only when it leaves projOn (its second event needs it active): 2430 s.
TEST(Earliest, ProjectorDwellsThenShutsDown) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = Example("presentation", "test1_cot.json");
  auto e = ComputeEarliestTimes(d, sp);
  ASSERT_TRUE(e);
  const int p = Automaton(d, "proj");
  EXPECT_EQ(e->arrival[p][Loc(d, "proj", "projOn")], Ticks(d, 30));
  EXPECT_EQ(e->arrival[p][Loc(d, "proj", "projConfirm")], Ticks(d, 1830));
  EXPECT_EQ(e->goal, Ticks(d, 2430));
  EXPECT_EQ(LowerBounds(d, sp).makespan_ticks, Ticks(d, 2430));
}

// Counted in events: connect, warm up, on, confirm (the shutdown constraint's first event), then
// cool down and off before its second event, which needs it active: 6 events, so the horizon
// search starts where the first plan is.
TEST(Earliest, EventsOfTestPrompt1) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = Example("presentation", "test1_cot.json");
  auto e = ComputeEarliestTimes(d, sp, Measure::kEvents);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->arrival[Automaton(d, "proj")][Loc(d, "proj", "projConfirm")], 4);
  EXPECT_EQ(e->goal, 6);
}

// Without the shutdown constraint the projector must still come back to projOff after its
// episode: 1830 s on, then through projCoolDown (60 s).
TEST(Earliest, ReturnAfterAnEpisode) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = Plan("presentation", testing::MustParse(R"({
    "initial_state": {"comp": "compOff", "conn": "disconnected", "proj": "projOff"},
    "end_state": {"maintenance_constraint": "true", "goal_constraint": "projl[i+1]==projOff"},
    "constraints": {"episodes": {"On": {"accepting_constraint": "projl[i]==projOn",
      "state_constraint": "projl[i]==projOn", "lower_bound": 100, "upper_bound": 200}}}})"));
  auto e = ComputeEarliestTimes(d, sp);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->goal, Ticks(d, 30 + 100 + 60));
}

// An accepting constraint wider than the state constraint gives no dwell: the projector may have
// been on before the episode started.
TEST(Earliest, NoDwellWhenTheEpisodeMayStartLater) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = Plan("presentation", testing::MustParse(R"({
    "initial_state": {"comp": "compOff", "conn": "disconnected", "proj": "projOff"},
    "end_state": {"maintenance_constraint": "true", "goal_constraint": "true"},
    "constraints": {"episodes": {"On": {
      "accepting_constraint": "projl[i]==projOn /\\ compl[i]==compOn",
      "state_constraint": "projl[i]==projOn", "lower_bound": 100, "upper_bound": 200}}}})"));
  auto e = ComputeEarliestTimes(d, sp);
  ASSERT_TRUE(e);
  const int p = Automaton(d, "proj");
  EXPECT_EQ(e->arrival[p][Loc(d, "proj", "projConfirm")], Ticks(d, 30));
  EXPECT_EQ(e->goal, Ticks(d, 30 + 100));  // the episode's start needs projOn (and compOn)
}

// The delete relaxation sees that someone must open a door (one robot's detour, 1) and that the
// door moves (2) besides each robot's cheapest route (5): 2 * 5 + 1 + 2 = 13. The graph bound,
// which ignores guards, says 10.
TEST(RelaxedCost, SomeoneOpensTheDoor) {
  const Domain& d = testing::ShippedDomain("search_rescue");
  StatePlan sp = Example("search_rescue", "test1.json");
  auto h = RelaxedCostBound(d, sp);
  ASSERT_TRUE(h);
  EXPECT_EQ(*h, 13);
  EXPECT_EQ(LowerBounds(d, sp).cost, 13);
}

// Guard landmarks: the projector cannot warm up unless the connection is connected, and the goal
// brings the connection back: the connection costs 2 although its goal is its initial location.
TEST(RelaxedCost, LandmarksCountTheHelperAndItsWayBack) {
  const Domain& d = testing::ShippedDomain("presentation");
  StatePlan sp = Plan("presentation", testing::MustParse(R"({
    "initial_state": {"comp": "compOff", "conn": "disconnected", "proj": "projOff"},
    "end_state": {"maintenance_constraint": "true",
      "goal_constraint": "connl[i+1]==disconnected /\\ projl[i+1]==projOff"},
    "constraints": {"episodes": {"On": {"accepting_constraint": "projl[i]==projOn",
      "state_constraint": "projl[i]==projOn", "lower_bound": 10, "upper_bound": 20}}}})"));
  // proj: off -> warm-up -> on -> cool-down -> off (4); conn: connect and disconnect (2).
  EXPECT_EQ(LowerBounds(d, sp).cost, 6);
}

// A relaxation without a plan gives no bound (the static checks report the conflict).
TEST(RelaxedCost, NoRelaxedPlanNoBound) {
  const Domain& d = testing::ShippedDomain("search_rescue");
  StatePlan sp = Example("search_rescue", "test1.json");
  sp.goal.expr = Expr{};
  sp.goal.expr.op = Expr::Op::kFalse;
  EXPECT_FALSE(RelaxedCostBound(d, sp));
}

// Assembly, "A to the floor, then B on A" (issue 18): B can be picked only once A has left it
// (a negated guard: blockA != onB), so arm picking B enters pickingB no earlier than 1 s and
// placingBonA no earlier than 2 s; the arm that places B must then get home (2 s): 4 s, the
// optimum (the graph bound said 1).
TEST(Earliest, AssemblyWaitsForTheBlockAboveAndTheArmsReturn) {
  const Domain& d = testing::ShippedDomain("assembly");
  StatePlan sp = Example("assembly", "test.json");
  auto e = ComputeEarliestTimes(d, sp);
  ASSERT_TRUE(e);
  const int arm2 = Automaton(d, "arm2");
  EXPECT_EQ(e->arrival[arm2][Loc(d, "arm2", "pickingB")], Ticks(d, 1));
  EXPECT_EQ(e->arrival[arm2][Loc(d, "arm2", "placingBonA")], Ticks(d, 2));
  EXPECT_EQ(e->goal, Ticks(d, 4));
  EXPECT_EQ(LowerBounds(d, sp).makespan_ticks, Ticks(d, 4));
}

Json TowerReverse() {
  return testing::MustParse(R"({
    "initial_state": {"arm1": "home", "arm2": "home", "blockA": "onB", "blockB": "onC",
                      "blockC": "onFloor"},
    "end_state": {"maintenance_constraint": "true", "goal_constraint":
      "arm1[i+1]==home /\\ arm2[i+1]==home /\\ blockA[i+1]==onFloor /\\ blockB[i+1]==onA /\\ blockC[i+1]==onB"},
    "objective": "makespan"})");
}

// Reversing a 3-block tower: each block needs a pick (1 s) and a place (2 s) by one arm, so
// three runs of 3 s on two arms: one arm does two, 6 s (the optimum; the precedences alone give
// 5 s). In events: per run the arm's way into holding, out of it and out of placing (3); in
// cost, the same three transitions per run.
TEST(Workload, ReversingATowerNeedsTwoRunsOnOneArm) {
  const Domain& d = testing::ShippedDomain("assembly");
  StatePlan sp = Plan("assembly", TowerReverse());
  auto e = ComputeEarliestTimes(d, sp);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->goal, Ticks(d, 5));
  const Workload w = ComputeWorkload(d, sp, nullptr, nullptr);
  EXPECT_EQ(w.makespan_ticks, Ticks(d, 6));
  EXPECT_EQ(w.events, 6);
  EXPECT_EQ(w.helper_cost, 9);
  for (std::size_t a = 0; a < d.automata.size(); ++a)
    EXPECT_EQ(w.helper[a], d.automata[a].name.rfind("arm", 0) == 0) << d.automata[a].name;
  const ObjectiveBounds b = LowerBounds(d, sp);
  EXPECT_EQ(b.makespan_ticks, Ticks(d, 6));
  // Blocks: 2 transitions each (6); arms: the larger of their own ways (0) and the work (9).
  EXPECT_GE(b.cost, 15);
  EXPECT_GE(b.events, 6);
}

// Releases: with A moved first, B's run cannot start before 1 s (A must have left it): the runs
// after 1 s are B's alone, 1 + 3 = 4 s, without the arms' return rule.
TEST(Workload, ReleasesSeeTheBlockAbove) {
  const Domain& d = testing::ShippedDomain("assembly");
  StatePlan sp = Example("assembly", "test.json");
  auto e = ComputeEarliestTimes(d, sp);
  ASSERT_TRUE(e);
  EXPECT_EQ(ComputeWorkload(d, sp, &*e, nullptr).makespan_ticks, Ticks(d, 4));
  EXPECT_EQ(ComputeWorkload(d, sp, nullptr, nullptr).makespan_ticks, Ticks(d, 3));
}

// One visit of the helper may carry the item twice (both of its transitions need the helper in
// `hold`): only the last is charged, so the bound is the true optimum, 2 s (home 1 s, hold 1 s),
// not 4 s. And a goal that reads a change gets no workload bound.
TEST(Workload, OneVisitCarryingTwoStepsIsChargedOnce) {
  Diagnostics diags;
  auto d = LoadDomain(testing::MustParse(R"({"name": "carry", "description": "", "automata": [
    {"name": "h", "locations": ["home", "hold"], "commands": ["go"], "transitions": [
      {"from": "home", "to": "hold", "guard": "hu[i]==go", "duration": [1, null]},
      {"from": "hold", "to": "home", "duration": [1, 1]}]},
    {"name": "x", "locations": ["p0", "p1", "p2"], "commands": [], "transitions": [
      {"from": "p0", "to": "p1", "guard": "hl[i]==hold"},
      {"from": "p1", "to": "p2", "guard": "hl[i]==hold"}]}]})"), diags);
  ASSERT_TRUE(d) << testing::AllErrors(diags);
  auto sp = LoadStatePlan(testing::MustParse(R"({"initial_state": {"h": "home", "x": "p0"},
    "end_state": {"maintenance_constraint": "true", "goal_constraint": "hl[i+1]==home /\\ xl[i+1]==p2"},
    "objective": "makespan"})"), *d, diags);
  ASSERT_TRUE(sp) << testing::AllErrors(diags);
  const Workload w = ComputeWorkload(*d, *sp, nullptr, nullptr);
  EXPECT_EQ(w.makespan_ticks, 2);
  EXPECT_EQ(LowerBounds(*d, *sp).makespan_ticks, 2);
  SolveOptions o;
  o.first_plan_ms = 0;
  o.bounds = ObjectiveBounds{};
  o.search = "g_first";
  o.max_horizon = 6;
  auto r = SolveDocument(*d, *sp, o);
  ASSERT_TRUE(std::holds_alternative<Json>(r));
  EXPECT_EQ(std::get<Json>(r)["objective"]["value"], 2);
  auto change = LoadStatePlan(testing::MustParse(R"({"initial_state": {"h": "home", "x": "p0"},
    "end_state": {"maintenance_constraint": "true", "goal_constraint": "xl[i]==p1 /\\ xl[i+1]==p2"},
    "objective": "makespan"})"), *d, diags);
  ASSERT_TRUE(change) << testing::AllErrors(diags);
  EXPECT_EQ(ComputeWorkload(*d, *change, nullptr, nullptr).makespan_ticks, 0);
}

}  // namespace
}  // namespace ctb
