// The first-plan engine from a replanning history (planner/search/history_nodes.cpp, issue 21):
// hand cases in search_rescue whose optima are worked out in the comments, and on random problems
// with random histories no plan the verifier refuses. The histories are read by planner/replan
// exactly as a replan reads them (BuildSituation); no solver runs here.
#include "planner/search/history_nodes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "planner/replan/situation.h"
#include "planner/search/first_plan.h"
#include "planner/verify/verify.h"
#include "random_problem.h"
#include "test_util.h"

namespace ctb {
namespace {

struct Replanned {
  replan::Situation s;
  FirstPlanResult r;
};

// Reads the request as Replan does and runs the engine from its history on the domain with the
// blocked transitions made impossible (the domain Replan solves).
Replanned FromHistory(const Domain& d, const StatePlan& sp, const Json& body, Objective objective,
                      long limit_ms = 2000, Keep keep = Keep::kNone) {
  Replanned out;
  ReplanRequest req;
  EXPECT_FALSE(ReadReplanRequest(body, req, nullptr)) << body.dump();
  auto e = replan::BuildSituation(d, sp, req, keep, out.s);
  EXPECT_FALSE(e) << (e ? e->ToString() : "");
  FirstPlanOptions o;
  o.objective = objective;
  o.time_limit_ms = limit_ms;
  o.history = std::make_shared<const History>(out.s.history);
  out.r = FindFirstPlan(out.s.model_domain, sp, o);
  EXPECT_EQ(out.r.rejected, 0);
  if (out.r.best) {
    auto problems = VerifyTrajectory(*out.r.best, out.s.model_domain, sp, out.s.tps);
    EXPECT_TRUE(problems.empty()) << problems[0];
  }
  return out;
}

StatePlan Test2() {
  return testing::ShippedStatePlan("search_rescue",
                                   testing::ConfigDir() + "/examples/search_rescue/test2.json");
}

// Test2's plan from the engine, by makespan, with no history: the plan a replan departs from.
FirstPlanResult Test2Plan(const Domain& d, const StatePlan& sp) {
  FirstPlanOptions o;
  o.objective = Objective::kMakespan;
  return FindFirstPlan(d, sp, o);
}

// The earliest future event (after the history's last) of a plan.
long FirstFutureTime(const Trajectory& t) {
  const int p = t.history->events();
  return p < t.goal_event ? t.events[p + 1] : -1;
}

bool Takes(const Trajectory& t, const Domain& d, const std::string& automaton,
           const std::string& from, const std::string& to) {
  const int a = d.AutomatonIndex(automaton);
  const Automaton& au = d.automata[a];
  for (const auto& f : t.fired)
    if (f.automaton == a && au.transitions[f.transition].from == au.LocationIndex(from) &&
        au.transitions[f.transition].to == au.LocationIndex(to))
      return true;
  return false;
}

// The optimal plan of test2 (robot 1 rescues person 1 at 11), executed up to now = 2: robot 1
// went to door 1 (0), arrived (1), opened it (1, open at 2). Nothing departs: the rest of the plan
// is still the best future, 11, and the history is the run's first stages.
TEST(FirstPlanFromHistory, AlongTheOptimalPlanNothingDepartsKeeps11) {
  const Domain& d = testing::ShippedDomain("search_rescue");
  StatePlan sp = Test2();
  FirstPlanResult plan = Test2Plan(d, sp);
  ASSERT_TRUE(plan.best);
  ASSERT_EQ(plan.makespan, 11);
  Json previous = TrajectoryToJson(*plan.best, d, sp, 1);
  Replanned x = FromHistory(d, sp, {{"now", 2}, {"trajectory", previous}}, Objective::kMakespan);
  ASSERT_GT(x.s.history.events(), 0);
  ASSERT_TRUE(x.r.best);
  EXPECT_EQ(x.r.makespan, 11);
  EXPECT_GE(FirstFutureTime(*x.r.best), 2);
  ASSERT_TRUE(x.r.best->history);
  EXPECT_EQ(x.r.best->history->events(), x.s.history.events());
}

// Robot 1 is blocked from going to door 1 before it leaves: through door 2 (10 s), it opens it
// (open at 11), enters, and reaches person 1 at 13.
TEST(FirstPlanFromHistory, BlockedBeforeLeavingGoesThroughDoor2In13) {
  const Domain& d = testing::ShippedDomain("search_rescue");
  StatePlan sp = Test2();
  Replanned x =
      FromHistory(d, sp, {{"now", 0}, {"executed", Json::array()}, {"blocked", Json::parse(R"([
      {"automaton": "robot1", "from": "outside", "to": "goingToDoor1"}])")}},
                  Objective::kMakespan);
  ASSERT_TRUE(x.r.best);
  EXPECT_EQ(x.r.makespan, 13);
  EXPECT_TRUE(Takes(*x.r.best, d, "robot1", "outside", "goingToDoor2"));
  EXPECT_FALSE(Takes(*x.r.best, d, "robot1", "outside", "goingToDoor1"));
}

// Robot 1 stands at door 1 at t = 1 and cannot open it: robot 2 comes (at door 1 at 2, opens it,
// open at 3), robot 1 enters at 3, door 3 at 7, person 1 at 12. The history's two transitions
// are the run's first ones.
TEST(FirstPlanFromHistory, AtDoor1UnableToOpenItRobot2ComesIn12) {
  const Domain& d = testing::ShippedDomain("search_rescue");
  StatePlan sp = Test2();
  Replanned x = FromHistory(d, sp, Json::parse(R"({"now": 1, "executed": [
      {"time": 0, "automaton": "robot1", "from": "outside", "to": "goingToDoor1"},
      {"time": 1, "automaton": "robot1", "from": "goingToDoor1", "to": "atDoor1"}],
      "blocked": [{"automaton": "robot1", "from": "atDoor1", "to": "door1Opening"}]})"),
                            Objective::kMakespan);
  ASSERT_TRUE(x.r.best);
  EXPECT_EQ(x.r.makespan, 12);
  EXPECT_TRUE(Takes(*x.r.best, d, "robot2", "atDoor1", "door1Opening"));
  EXPECT_TRUE(Takes(*x.r.best, d, "robot1", "atDoor1", "insideRoom1"));
  ASSERT_GE(x.r.best->fired.size(), 2u);
  EXPECT_EQ(x.r.best->fired[0].event, 1);
  EXPECT_EQ(x.r.best->fired[1].event, 2);
}

// Nothing has happened by now = 5 (the team waited): every future event is at 5 or later, so
// person 1 is reached at 5 + 11 = 16. Without the history the same problem takes 11.
TEST(FirstPlanFromHistory, NoEventBeforeNow) {
  const Domain& d = testing::ShippedDomain("search_rescue");
  StatePlan sp = Test2();
  Replanned x = FromHistory(d, sp, {{"now", 5}, {"executed", Json::array()}}, Objective::kMakespan);
  ASSERT_TRUE(x.r.best);
  EXPECT_EQ(x.r.makespan, 16);
  EXPECT_EQ(FirstFutureTime(*x.r.best), 5);
  EXPECT_EQ(x.r.best->events[0], 0);
}

// The history's cost counts: by cost, the whole run's cost is the history's (robot 1's two moves)
// plus the future's.
TEST(FirstPlanFromHistory, TheCostIsTheWholeRuns) {
  const Domain& d = testing::ShippedDomain("search_rescue");
  StatePlan sp = Test2();
  Replanned x = FromHistory(d, sp, Json::parse(R"({"now": 1, "executed": [
      {"time": 0, "automaton": "robot1", "from": "outside", "to": "goingToDoor1"},
      {"time": 1, "automaton": "robot1", "from": "goingToDoor1", "to": "atDoor1"}]})"),
                            Objective::kCost);
  ASSERT_TRUE(x.r.best);
  EXPECT_EQ(x.r.cost, TrajectoryCost(*x.r.best, x.s.model_domain));
  EXPECT_GE(x.r.cost, x.s.history_cost);
  EXPECT_GT(x.s.history_cost, 0);
}

// keep "started" is left to the exact engines.
TEST(FirstPlanFromHistory, DeclinesKeepStarted) {
  const Domain& d = testing::ShippedDomain("search_rescue");
  StatePlan sp = Test2();
  FirstPlanResult plan = Test2Plan(d, sp);
  ASSERT_TRUE(plan.best);
  Replanned x =
      FromHistory(d, sp, {{"now", 1}, {"trajectory", TrajectoryToJson(*plan.best, d, sp, 1)}},
                  Objective::kMakespan, 2000, Keep::kStarted);
  ASSERT_FALSE(x.s.history.keep_next.empty());
  EXPECT_FALSE(x.r.best);
  EXPECT_NE(x.r.declined.find("started"), std::string::npos) << x.r.declined;
}

// The history's stages are taken as reported: a robot that arrived at door 1 late (at 3, the move
// lasts 1 s) is where the history has it, since 3, and the monitors follow the stages.
TEST(HistoryNodes, StagesAreTheHistorysAsReported) {
  const Domain& d = testing::ShippedDomain("search_rescue");
  StatePlan sp = Test2();
  ReplanRequest req;
  ASSERT_FALSE(ReadReplanRequest(Json::parse(R"({"now": 4, "executed": [
      {"time": 0, "automaton": "robot1", "from": "outside", "to": "goingToDoor1"},
      {"time": 3, "automaton": "robot1", "from": "goingToDoor1", "to": "atDoor1"}]})"),
                                 req, nullptr));
  replan::Situation s;
  ASSERT_FALSE(replan::BuildSituation(d, sp, req, Keep::kNone, s));
  search::Expander ex(d, sp, 1);
  std::vector<search::Node> nodes = search::HistoryNodes(ex, d, s.history);
  ASSERT_EQ(nodes.size(), 3u);
  const int r1 = d.AutomatonIndex("robot1");
  EXPECT_EQ(nodes[2].time, 3);
  EXPECT_EQ(nodes[2].entry[r1], 3);
  EXPECT_EQ(nodes[2].loc[r1], d.automata[r1].LocationIndex("atDoor1"));
  EXPECT_EQ(nodes[2].parent, 1);
  EXPECT_FALSE(nodes[2].done);
  // A state plan whose goal the history already reached before its last stage: no start.
  Diagnostics diags;
  auto reached = LoadStatePlan(testing::MustParse(R"({
    "initial_state": {"robot1": "outside", "robot2": "outside", "door1": "closed",
                      "door2": "closed", "door3": "open"},
    "end_state": {"maintenance_constraint": "true", "goal_constraint": "robot1[i+1]==goingToDoor1"}})"),
                               d, diags);
  ASSERT_TRUE(reached) << testing::AllErrors(diags);
  search::Expander ex2(d, *reached, 1);
  EXPECT_TRUE(search::HistoryNodes(ex2, d, s.history).empty());
}

// Random problems (the differential suite's generator), a plan from the engine, a random now
// along it and a random departure: every plan the engine finds from the history passes the
// verifier (history stages as reported, the rules from their entry times, every event at or after
// now).
TEST(FirstPlanFromHistory, RandomHistoriesNeverGiveAPlanTheVerifierRefuses) {
  int ran = 0, found = 0;
  for (unsigned seed = 300; seed < 420; ++seed) {
    testing::ProblemGenerator gen(seed);
    testing::RandomProblem p = gen.Next();
    Diagnostics diags;
    auto d = LoadDomain(p.domain, diags);
    auto sp = d ? LoadStatePlan(p.state_plan, *d, diags) : std::nullopt;
    ASSERT_TRUE(sp) << "seed " << seed << testing::AllErrors(diags);
    const long tps = std::lround(1.0 / d->time_resolution);
    FirstPlanOptions o;
    o.objective = sp->objective;
    o.time_limit_ms = 100;
    FirstPlanResult plan = FindFirstPlan(*d, *sp, o);
    if (!plan.best) continue;
    std::mt19937 rng(seed);
    auto pick = [&](long lo, long hi) { return std::uniform_int_distribution<long>(lo, hi)(rng); };
    Json body = {{"now", pick(0, plan.makespan / tps)},
                 {"trajectory", TrajectoryToJson(*plan.best, *d, *sp, tps)}};
    const int a = static_cast<int>(pick(0, static_cast<long>(d->automata.size()) - 1));
    const Automaton& au = d->automata[a];
    if (seed % 3 == 1) {
      const long l = pick(0, static_cast<long>(au.locations.size()) - 1);
      body["observed"] = {{au.name, {{"location", au.locations[l]}}}};
    } else if (seed % 3 == 2 && !au.transitions.empty()) {
      const Transition& t = au.transitions[pick(0, static_cast<long>(au.transitions.size()) - 1)];
      body["blocked"] = {
          {{"automaton", au.name}, {"from", au.locations[t.from]}, {"to", au.locations[t.to]}}};
    }
    SCOPED_TRACE("seed " + std::to_string(seed) + " request " + body.dump() + "\n" + p.Describe());
    Replanned x = FromHistory(*d, *sp, body, sp->objective, 100);
    if (!x.r.declined.empty()) continue;
    ++ran;
    found += x.r.best ? 1 : 0;
  }
  EXPECT_GT(ran, 40);
  EXPECT_GT(found, ran / 3) << found << " of " << ran;
  std::printf("the engine ran from %d random histories and found %d plans\n", ran, found);
}

}  // namespace
}  // namespace ctb
