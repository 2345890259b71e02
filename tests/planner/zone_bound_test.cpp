// The makespan bound of the zone search with a deadline (analyze/bounds.h, RaiseMakespanBound):
// whole ticks, the commands of the transitions taken at an event, and the pruning of states from
// which the goal cannot come in time (analyze/earliest.h, RemainingTime). Soundness against the
// exact engine (Gecode alone, no bound told, plans of at most 10 events): the bound never exceeds
// its optimum on random problems of the assembly kind, of devices taking turns, and of the
// general generator; it meets the optimum on most. Then re-stacking with the shipped assembly
// domain's race guards (which read the other arm's command) and a solve proven by it.
// Budgets are counted in states, never in time: the results do not depend on the machine.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <string>
#include <variant>

#include "planner/analyze/bounds.h"
#include "planner/analyze/earliest.h"
#include "planner/solve/solve.h"
#include "exact_engine.h"
#include "random_helpers.h"
#include "random_problem.h"
#include "test_util.h"
#include "turns_problem.h"

namespace ctb {
namespace zone_bound_test {
namespace {

constexpr MakespanProofBudget kBudget{600000, 200000};  // states decide, not the clock

// The exact engine's optimum makespan in ticks; -1 when it has no plan within `events` events.
long ExactMakespan(const Domain& d, const StatePlan& sp, const std::string& what, int events = 10) {
  auto r = SolveDocument(d, sp, testing::ExactEngineAlone(Objective::kMakespan, events));
  EXPECT_TRUE(std::holds_alternative<Json>(r)) << what;
  if (!std::holds_alternative<Json>(r)) return -1;
  const Json& x = std::get<Json>(r);
  EXPECT_TRUE(x["status"] == "optimal" || x["status"] == "infeasible") << x["status"] << what;
  if (x["status"] != "optimal") return -1;
  return std::lround(x["objective"]["value"].get<double>() / d.time_resolution);
}

struct Tally {
  int compared = 0, tight = 0;
};

// The bound asked with a plan 2 ticks above the optimum: never above the optimum.
void Check(const Domain& d, const StatePlan& sp, const std::string& what, Tally& t) {
  if (!RemainingTime::Applies(sp)) return;
  const long optimum = ExactMakespan(d, sp, what);
  if (optimum < 0) return;
  const MakespanProof p = RaiseMakespanBound(d, sp, 0, optimum + 2, kBudget);
  EXPECT_LE(p.makespan_ticks, optimum) << what;
  ++t.compared;
  t.tight += p.makespan_ticks == optimum;
}

// The shipped assembly domain (2 arms, 3 blocks) with its race guards: an arm must not place onto
// a block the arm numbered below is commanded to pick at that stage, and so on. The search reads
// the command of the transition each arm takes; without that it would follow the races, whose
// runs are shorter. A makespan state plan from these towers (block -> location).
StatePlan Restack(const std::map<std::string, std::string>& from,
                  const std::map<std::string, std::string>& to) {
  Json j = testing::MustParse(R"({"initial_state": {"arm1": "home", "arm2": "home"},
    "end_state": {"maintenance_constraint": "true", "goal_constraint": "true"},
    "objective": "makespan"})");
  std::string goal = "arm1[i+1]==home /\\ arm2[i+1]==home";
  for (const auto& [b, l] : from) j["initial_state"]["block" + b] = l;
  for (const auto& [b, l] : to) goal += " /\\ block" + b + "[i+1]==" + l;
  j["end_state"]["goal_constraint"] = goal;
  Diagnostics diags;
  auto sp = LoadStatePlan(j, testing::ShippedDomain("assembly"), diags);
  if (!sp) ADD_FAILURE() << testing::AllErrors(diags);
  return sp ? *sp : StatePlan{};
}

// The estimate the search prunes with (RemainingTime, with its cached tables: distances, guards as
// lists of atoms) from the initial state, every automaton just entered, is the earliest goal of
// ComputeEarliestTimes: the same rules, the same settled arrivals.
TEST(ZoneBound, TheRemainingTimeFromTheStartIsTheEarliestGoal) {
  int compared = 0, positive = 0;
  auto check = [&](const Domain& d, const StatePlan& sp, const std::string& what) {
    if (!RemainingTime::Applies(sp)) return;
    const auto e = ComputeEarliestTimes(d, sp);
    ASSERT_TRUE(e) << what;
    const long rest = RemainingTime(d, sp).Goal(sp.initial, std::vector<long>(d.automata.size(), 0));
    EXPECT_EQ(rest, e->goal) << what;
    ++compared;
    positive += rest > 0;
  };
  for (unsigned seed = 100; seed < 130; ++seed) {
    testing::RandomProblem p = testing::HelperProblemGenerator(seed).Next();
    Diagnostics diags;
    auto d = LoadDomain(p.domain, diags);
    auto sp = d ? LoadStatePlan(p.state_plan, *d, diags) : std::nullopt;
    ASSERT_TRUE(sp) << testing::AllErrors(diags) << p.Describe();
    check(*d, *sp, "helpers seed " + std::to_string(seed));
  }
  for (unsigned seed = 0; seed < 60; ++seed) {
    testing::RandomProblem p = testing::ProblemGenerator(seed).Next();
    Diagnostics diags;
    auto d = LoadDomain(p.domain, diags);
    auto sp = d ? LoadStatePlan(p.state_plan, *d, diags) : std::nullopt;
    if (sp) check(*d, *sp, "random seed " + std::to_string(seed));
  }
  const Domain& assembly = testing::ShippedDomain("assembly");
  check(assembly, Restack({{"A", "onB"}, {"B", "onC"}, {"C", "onFloor"}},
                          {{"A", "onC"}, {"B", "onFloor"}, {"C", "onB"}}), "re-stacking");
  EXPECT_GE(compared, 40);
  EXPECT_GE(positive, 30);
}

TEST(ZoneBound, NeverAboveTheExactOptimumOfHelperProblems) {
  Tally t;
  for (unsigned seed = 100; seed < 105; ++seed) {
    testing::RandomProblem p = testing::HelperProblemGenerator(seed).Next();
    Diagnostics diags;
    auto d = LoadDomain(p.domain, diags);
    ASSERT_TRUE(d) << testing::AllErrors(diags) << p.Describe();
    auto sp = LoadStatePlan(p.state_plan, *d, diags);
    ASSERT_TRUE(sp) << testing::AllErrors(diags) << p.Describe();
    Check(*d, *sp, "seed " + std::to_string(seed) + "\n" + p.Describe(), t);
  }
  std::cout << t.compared << " compared, tight " << t.tight << "\n";
  EXPECT_GE(t.compared, 4);
  EXPECT_GE(t.tight, 3) << "the search met few optima";
}

TEST(ZoneBound, NeverAboveTheExactOptimumOfRandomProblems) {
  Tally t;
  for (unsigned seed = 0; seed < 40 && t.compared < 6; ++seed) {
    testing::RandomProblem p = testing::ProblemGenerator(seed).Next();
    Diagnostics diags;
    auto d = LoadDomain(p.domain, diags);
    if (!d) continue;
    auto sp = LoadStatePlan(p.state_plan, *d, diags);
    if (!sp) continue;
    Check(*d, *sp, "seed " + std::to_string(seed) + "\n" + p.Describe(), t);
  }
  std::cout << t.compared << " compared, tight " << t.tight << "\n";
  EXPECT_GE(t.compared, 5);
  EXPECT_GE(t.tight, 3);
}

TEST(ZoneBound, NeverAboveTheExactOptimumOfDevicesTakingTurns) {
  std::mt19937 rng(2911);
  Tally t;
  for (int i = 0; i < 4; ++i) {
    std::vector<testing::Device> devs;
    for (int k = 0; k < 3; ++k)
      devs.push_back({static_cast<int>(rng() % 3), 1 + static_cast<int>(rng() % 3),
                      static_cast<int>(rng() % 3), rng() % 4 == 0});
    auto p = testing::MakeTurns(devs, testing::ExclusionForm::kNotBoth);
    Check(p.domain, p.plan, testing::TurnPlanJson(devs, testing::ExclusionForm::kNotBoth).dump(), t);
  }
  EXPECT_GE(t.compared, 4);
  EXPECT_GE(t.tight, 3);
}

TEST(ZoneBound, MeetsTheExactOptimumOfReStackingWithRaceGuards) {
  const Domain& d = testing::ShippedDomain("assembly");
  const std::vector<std::pair<std::map<std::string, std::string>, std::map<std::string, std::string>>>
      cases = {
          // the middle block to the top: A on C on B from A on B on C
          {{{"A", "onB"}, {"B", "onC"}, {"C", "onFloor"}}, {{"A", "onC"}, {"B", "onFloor"}, {"C", "onB"}}},
          // two on the floor onto the third
          {{{"A", "onFloor"}, {"B", "onFloor"}, {"C", "onFloor"}}, {{"A", "onB"}, {"B", "onC"}, {"C", "onFloor"}}},
      };
  Tally t;
  for (const auto& [from, to] : cases) {
    const StatePlan sp = Restack(from, to);
    const long optimum = ExactMakespan(d, sp, "re-stacking", 16);
    ASSERT_GT(optimum, 0);
    const MakespanProof p = RaiseMakespanBound(d, sp, 0, optimum, kBudget);
    EXPECT_EQ(p.makespan_ticks, optimum) << "case " << t.compared;
    ++t.compared;
  }
}

// Re-stacking four blocks with the race guards (tests/planner/data/assembly_4x2.json:
// bench/assembly_proofs.py's `assembly("ABCD", 2)`; bench/restack.py's problem 3 with two arms:
// A, B/D/C to A/C/B/D): the first plan's 7 s was `feasible` against a bound of 6 until this
// search, which shows that no plan ends within 6 s.
TEST(ZoneBound, ProvesAReStackingPlanOptimal) {
  std::ifstream in(testing::SourceDir() + "/tests/planner/data/assembly_4x2.json");
  const Json dom = testing::MustParse(std::string(std::istreambuf_iterator<char>(in), {}));
  Diagnostics diags;
  auto d = LoadDomain(dom, diags);
  ASSERT_TRUE(d) << testing::AllErrors(diags);
  Json plan = testing::MustParse(R"({
    "initial_state": {"arm1": "home", "arm2": "home", "blockA": "onFloor", "blockB": "onD",
                      "blockC": "onFloor", "blockD": "onC"},
    "end_state": {"maintenance_constraint": "true", "goal_constraint":
      "arm1[i+1]==home /\\ arm2[i+1]==home /\\ blockA[i+1]==onC /\\ blockB[i+1]==onD /\\ blockC[i+1]==onB /\\ blockD[i+1]==onFloor"},
    "objective": "makespan"})");
  auto sp = LoadStatePlan(plan, *d, diags);
  ASSERT_TRUE(sp) << testing::AllErrors(diags);
  const MakespanProof p = RaiseMakespanBound(*d, *sp, 6, 7, kBudget);
  EXPECT_EQ(p.makespan_ticks, 7);
  EXPECT_EQ(p.searches, 1);
  // A cancelled solve (a client gone) stops the search: no proof, the bound as given.
  std::atomic<bool> cancelled{true};
  MakespanProofBudget stopped = kBudget;
  stopped.cancel = &cancelled;
  EXPECT_EQ(RaiseMakespanBound(*d, *sp, 6, 7, stopped).makespan_ticks, 6);
  SolveOptions o;
  o.objective = Objective::kMakespan;
  o.zone_proof_ms = 600000;  // the search ends by its states
  auto r = SolveDocument(*d, *sp, o);
  ASSERT_TRUE(std::holds_alternative<Json>(r)) << std::get<Error>(r).ToString();
  const Json& x = std::get<Json>(r);
  EXPECT_EQ(x["status"], "optimal");
  EXPECT_EQ(x["objective"]["value"], 7);
}

}  // namespace
}  // namespace zone_bound_test
}  // namespace ctb
