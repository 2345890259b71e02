// Lower bounds that hold for every plan (issue 9): earliest times (analyze/earliest.h), the
// delete relaxation (analyze/relaxed_cost.h) and guard landmarks (solve/bounds.h). Soundness on
// random problems is checked against every plan the brute-force enumeration finds.
#include "planner/analyze/earliest.h"

#include <gtest/gtest.h>

#include "planner/analyze/relaxed_cost.h"
#include "planner/solve/bounds.h"
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

}  // namespace
}  // namespace ctb
