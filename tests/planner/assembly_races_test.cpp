// The shipped assembly domain (config/domains/assembly.json, tools/gen_domains.py) against races
// between two arms: a block must not land on one that another arm is taking, and an arm must
// not start taking a block another arm is taking or putting something onto. Transitions of
// several automata at one event read the stage before it, so each rule needs the other arm's
// location (what it already does) and, at one stage, its command (arm 1 has priority):
// ../shared/design/domains.md, "turn 3", and bench/results/restack.md, "Correction".
//
// Each run below is built by hand, event by event, and replayed by the independent verifier.
// Before the guards were added every racing run was a valid plan (the verifier found nothing);
// now each has exactly one problem: the racing arm's guard at the racing event.
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "planner/verify/verify.h"
#include "test_util.h"

namespace ctb {
namespace {

struct Move {
  const char* automaton;
  const char* to;
};
struct Event {
  long time;  // seconds (one tick per second)
  std::vector<Move> moves;
};

const Domain& Assembly() { return testing::ShippedDomain("assembly"); }

// A makespan state plan: every block on the floor, both arms home; the goal as given.
StatePlan Plan(const std::string& goal) {
  Json j = testing::MustParse(R"({
    "initial_state": {"arm1": "home", "arm2": "home", "blockA": "onFloor", "blockB": "onFloor",
                      "blockC": "onFloor"},
    "end_state": {"maintenance_constraint": "true", "goal_constraint": "true"},
    "objective": "makespan"})");
  j["end_state"]["goal_constraint"] = goal;
  Diagnostics diags;
  auto sp = LoadStatePlan(j, Assembly(), diags);
  if (!sp) ADD_FAILURE() << testing::AllErrors(diags);
  return sp ? *sp : StatePlan{};
}

// The run from the plan's initial state through these events; a commanded transition's command
// is issued in the stage before its event. The last event is the goal event.
Trajectory BuildRun(const StatePlan& sp, const std::vector<Event>& events) {
  const Domain& d = Assembly();
  const std::size_t n = events.size();
  Trajectory t;
  t.events.push_back(0);
  t.locations.resize(d.automata.size());
  t.commands.assign(d.automata.size(), std::vector<int>(n + 1, 0));
  for (std::size_t a = 0; a < d.automata.size(); ++a) t.locations[a].push_back(sp.initial[a]);
  for (std::size_t k = 1; k <= n; ++k) {
    t.events.push_back(events[k - 1].time);
    for (auto& l : t.locations) l.push_back(l.back());
    for (const Move& m : events[k - 1].moves) {
      const int a = d.AutomatonIndex(m.automaton);
      const Automaton& au = d.automata[a];
      const int from = t.locations[a][k - 1], to = au.LocationIndex(m.to);
      int ti = -1;
      for (std::size_t i = 0; i < au.transitions.size(); ++i)
        if (au.transitions[i].from == from && au.transitions[i].to == to) ti = static_cast<int>(i);
      if (ti < 0 || to < 0) {
        ADD_FAILURE() << m.automaton << " has no transition to " << m.to << " at event " << k;
        continue;
      }
      if (au.transitions[ti].commanded) t.commands[a][k - 1] = au.transitions[ti].command;
      t.locations[a][k] = to;
      t.fired.push_back({static_cast<int>(k), a, ti});
    }
  }
  t.goal_event = t.horizon = static_cast<int>(n);
  return t;
}

std::string Join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += x + "\n";
  return s;
}

// Exactly one problem: `arm`'s guard is false at event k.
void ExpectOnlyTheGuardOf(const std::vector<std::string>& problems, const std::string& arm, int k) {
  ASSERT_EQ(problems.size(), 1u) << Join(problems);
  EXPECT_EQ(problems[0].rfind("'" + arm + "' at event " + std::to_string(k) + " ", 0), 0u)
      << problems[0];
  EXPECT_NE(problems[0].find("is false on the stage before"), std::string::npos) << problems[0];
}

const char* kAOnBOnC =
    "blockA[i+1]==onB /\\ blockB[i+1]==onC /\\ arm1[i+1]==home /\\ arm2[i+1]==home";

// The control: the same helper builds a valid run (domains.md, the thesis' example from A on B
// on C: A to the floor, then B on A, 4 s; here from the floor: B on C, then A on B, 3 s).
TEST(AssemblyRaces, TheOrderlyRunIsAPlan) {
  StatePlan sp = Plan(kAOnBOnC);
  Trajectory t = BuildRun(sp, {{0, {{"arm1", "pickingA"}, {"arm2", "pickingB"}}},
                               {1, {{"arm1", "holdingA"}, {"arm2", "holdingB"}}},
                               {1, {{"blockA", "inArm1"}, {"blockB", "inArm2"}}},
                               {1, {{"arm2", "placingBonC"}}},
                               {1, {{"blockB", "onC"}}},
                               {1, {{"arm1", "placingAonB"}}},
                               {1, {{"blockA", "onB"}}},
                               {3, {{"arm1", "home"}, {"arm2", "home"}}}});
  auto problems = VerifyTrajectory(t, Assembly(), sp, 1);
  EXPECT_TRUE(problems.empty()) << Join(problems);
}

// The race of restack.md's plans: arm 1 starts placing A onto B; at the event A lands on B,
// arm 2 starts picking B (A is still in arm 1 on the stage its guard reads) and carries B to C
// with A on it. Picking B now needs that no other arm is placing onto B.
TEST(AssemblyRaces, NoPickOfABlockAnotherArmIsPlacingOnto) {
  StatePlan sp = Plan(kAOnBOnC);
  Trajectory t = BuildRun(sp, {{0, {{"arm1", "pickingA"}}},
                               {1, {{"arm1", "holdingA"}}},
                               {1, {{"blockA", "inArm1"}}},
                               {1, {{"arm1", "placingAonB"}}},
                               {1, {{"blockA", "onB"}, {"arm2", "pickingB"}}},
                               {2, {{"arm2", "holdingB"}}},
                               {2, {{"blockB", "inArm2"}}},
                               {2, {{"arm2", "placingBonC"}}},
                               {2, {{"blockB", "onC"}}},
                               {3, {{"arm1", "home"}}},
                               {4, {{"arm2", "home"}}}});
  ExpectOnlyTheGuardOf(VerifyTrajectory(t, Assembly(), sp, 1), "arm2", 5);
}

// The other way round: arm 2 is picking B when arm 1 starts placing A onto it (nothing is on B
// and B is in no arm yet). Placing onto B now needs that no other arm is picking B.
TEST(AssemblyRaces, NoPlacingOntoABlockAnotherArmIsPicking) {
  StatePlan sp = Plan(kAOnBOnC);
  Trajectory t = BuildRun(sp, {{0, {{"arm1", "pickingA"}}},
                               {1, {{"arm1", "holdingA"}}},
                               {1, {{"blockA", "inArm1"}, {"arm2", "pickingB"}}},
                               {1, {{"arm1", "placingAonB"}}},
                               {1, {{"blockA", "onB"}}},
                               {2, {{"arm2", "holdingB"}}},
                               {2, {{"blockB", "inArm2"}}},
                               {2, {{"arm2", "placingBonC"}}},
                               {2, {{"blockB", "onC"}}},
                               {3, {{"arm1", "home"}}},
                               {4, {{"arm2", "home"}}}});
  ExpectOnlyTheGuardOf(VerifyTrajectory(t, Assembly(), sp, 1), "arm1", 4);
}

// Arm 2 holds B (B moves into it at the next event, reading the stage in which it still lies on
// the floor); arm 1 starts placing A onto B at that event. Placing onto B needs that no other
// arm is holding B either.
TEST(AssemblyRaces, NoPlacingOntoABlockAnotherArmIsAboutToTake) {
  StatePlan sp = Plan(kAOnBOnC);
  Trajectory t =
      BuildRun(sp, {{0, {{"arm1", "pickingA"}, {"arm2", "pickingB"}}},
                    {1, {{"arm1", "holdingA"}, {"arm2", "holdingB"}}},
                    {1, {{"blockA", "inArm1"}, {"blockB", "inArm2"}, {"arm1", "placingAonB"}}},
                    {1, {{"blockA", "onB"}, {"arm2", "placingBonC"}}},
                    {1, {{"blockB", "onC"}}},
                    {3, {{"arm1", "home"}, {"arm2", "home"}}}});
  ExpectOnlyTheGuardOf(VerifyTrajectory(t, Assembly(), sp, 1), "arm1", 3);
}

// Arm 1 holds B (B moves into it at the next event); arm 2 starts picking B at that event and,
// once arm 1 has put B on C, takes it from there. Picking B needs that no other arm is holding
// B: the same rule as "not picking B", one stage later.
TEST(AssemblyRaces, NoPickOfABlockAnotherArmIsAboutToTake) {
  StatePlan sp = Plan("blockB[i+1]==onA /\\ arm1[i+1]==home /\\ arm2[i+1]==home");
  Trajectory t = BuildRun(sp, {{0, {{"arm1", "pickingB"}}},
                               {1, {{"arm1", "holdingB"}}},
                               {1, {{"blockB", "inArm1"}, {"arm2", "pickingB"}}},
                               {1, {{"arm1", "placingBonC"}}},
                               {1, {{"blockB", "onC"}}},
                               {2, {{"arm2", "holdingB"}}},
                               {2, {{"blockB", "inArm2"}}},
                               {2, {{"arm2", "placingBonA"}}},
                               {2, {{"blockB", "onA"}}},
                               {3, {{"arm1", "home"}}},
                               {4, {{"arm2", "home"}}}});
  ExpectOnlyTheGuardOf(VerifyTrajectory(t, Assembly(), sp, 1), "arm2", 3);
}

// Both commands at one stage, both guards reading the stage before (domains.md, turn 3): arm 1
// places A onto B while arm 2 starts picking B. Arm 1 has priority: arm 2's pick needs that arm 1
// is not commanded to place onto B.
TEST(AssemblyRaces, NoPickAtTheStageArm1IsCommandedToPlaceOntoTheBlock) {
  StatePlan sp = Plan(kAOnBOnC);
  Trajectory t = BuildRun(sp, {{0, {{"arm1", "pickingA"}}},
                               {1, {{"arm1", "holdingA"}}},
                               {1, {{"blockA", "inArm1"}}},
                               {1, {{"arm1", "placingAonB"}, {"arm2", "pickingB"}}},
                               {1, {{"blockA", "onB"}}},
                               {2, {{"arm2", "holdingB"}}},
                               {2, {{"blockB", "inArm2"}}},
                               {2, {{"arm2", "placingBonC"}}},
                               {2, {{"blockB", "onC"}}},
                               {3, {{"arm1", "home"}}},
                               {4, {{"arm2", "home"}}}});
  ExpectOnlyTheGuardOf(VerifyTrajectory(t, Assembly(), sp, 1), "arm2", 4);
}

// And the mirror: arm 1 starts picking B while arm 2 starts placing A onto it. Arm 2's placing
// needs that arm 1 is not commanded to pick B.
TEST(AssemblyRaces, NoPlacingAtTheStageArm1IsCommandedToPickTheBlock) {
  StatePlan sp = Plan(kAOnBOnC);
  Trajectory t = BuildRun(sp, {{0, {{"arm2", "pickingA"}}},
                               {1, {{"arm2", "holdingA"}}},
                               {1, {{"blockA", "inArm2"}}},
                               {1, {{"arm1", "pickingB"}, {"arm2", "placingAonB"}}},
                               {1, {{"blockA", "onB"}}},
                               {2, {{"arm1", "holdingB"}}},
                               {2, {{"blockB", "inArm1"}}},
                               {2, {{"arm1", "placingBonC"}}},
                               {2, {{"blockB", "onC"}}},
                               {3, {{"arm2", "home"}}},
                               {4, {{"arm1", "home"}}}});
  ExpectOnlyTheGuardOf(VerifyTrajectory(t, Assembly(), sp, 1), "arm2", 4);
}

}  // namespace
}  // namespace ctb
