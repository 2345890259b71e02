// The turn-taking bound (planner/analyze/turns.h) against exact optima: small random devices that
// warm up one at a time (with releases, tails, and devices that may skip their warm-up), each
// solved by the exact engine alone with no bound to stop at; the bound must never exceed the
// optimum, must meet it on some, and the default solve must end optimal at the same value.
#include <gtest/gtest.h>

#include <optional>
#include <random>
#include <string>
#include <variant>

#include "planner/analyze/bounds.h"
#include "planner/analyze/turns.h"
#include "planner/solve/solve.h"
#include "exact_engine.h"
#include "turns_problem.h"

namespace ctb {
namespace {

using testing::Device;

// One problem of devices: the turn bound, the exact engine's optimum (alone, no bound, plans of at
// most exact_horizon events) and the bounds without the turns; the default solve (first plan,
// neighbourhood rounds, bounds, Gecode; max_horizon when given) must end optimal at the optimum.
struct AgainstExact {
  long bound = 0, optimum = 0, others = 0;
  std::string plan;  // the state plan, for messages
};

void CompareWithExact(const std::vector<Device>& devs, testing::ExclusionForm form, int exact_horizon,
                      std::optional<int> solve_horizon, AgainstExact& out) {
  auto p = testing::MakeTurns(devs, form);
  auto e = ComputeEarliestTimes(p.domain, p.plan);
  out.bound = ComputeTurnBound(p.domain, p.plan, e ? &*e : nullptr).makespan_ticks;
  out.others = LowerBounds(p.domain, p.plan, BoundOptions{.turns = false}).makespan_ticks;
  out.plan = testing::TurnPlanJson(devs, form).dump();
  auto exact = SolveDocument(p.domain, p.plan, testing::ExactEngineAlone(Objective::kMakespan, exact_horizon));
  ASSERT_TRUE(std::holds_alternative<Json>(exact)) << std::get<Error>(exact).ToString();
  const Json& x = std::get<Json>(exact);
  ASSERT_EQ(x["status"], "optimal") << out.plan;
  out.optimum = std::lround(x["objective"]["value"].get<double>() / p.domain.time_resolution);

  SolveOptions fast;
  fast.objective = Objective::kMakespan;
  fast.time_limit_ms = 120000;
  if (solve_horizon) fast.max_horizon = *solve_horizon;
  auto r = SolveDocument(p.domain, p.plan, fast);
  ASSERT_TRUE(std::holds_alternative<Json>(r)) << std::get<Error>(r).ToString();
  EXPECT_EQ(std::get<Json>(r)["status"], "optimal") << out.plan;
  EXPECT_EQ(std::get<Json>(r)["objective"]["value"], x["objective"]["value"]) << out.plan;
}

TEST(TurnsSolve, TheBoundNeverExceedsAnExactOptimum) {
  std::mt19937 rng(29);
  int tight = 0, bites = 0;
  for (int i = 0; i < 6; ++i) {
    std::vector<Device> devs;
    const int n = 2 + i % 2;
    for (int k = 0; k < n; ++k)
      devs.push_back({static_cast<int>(rng() % 3), 1 + static_cast<int>(rng() % 3),
                      static_cast<int>(rng() % 3), rng() % 4 == 0});
    AgainstExact c;
    ASSERT_NO_FATAL_FAILURE(CompareWithExact(devs, testing::ExclusionForm::kNotBoth, 12, std::nullopt, c));
    EXPECT_LE(c.bound, c.optimum) << "case " << i << ": " << c.plan;
    tight += c.bound == c.optimum;
    bites += c.bound > c.others;
  }
  EXPECT_GE(tight, 2) << "the bound met no optimum";
  EXPECT_GE(bites, 2) << "the bound never rose above the others";
}

// At most two warm at once (every three excluded, planner/analyze/turns.h "At most k"): on small
// random devices the two-machine bound never exceeds the exact engine's optimum, and the default
// solve (first plan, neighbourhood rounds, bounds, Gecode) ends optimal at that value.
TEST(TurnsSolve, AtMostTwoAtOnceNeverAboveAnExactOptimum) {
  std::mt19937 rng(292);
  int bites = 0;
  for (int i = 0; i < 4; ++i) {
    std::vector<Device> devs;
    const int n = 3 + i % 2;
    for (int k = 0; k < n; ++k)
      devs.push_back({static_cast<int>(rng() % 3), 2 + static_cast<int>(rng() % 3),
                      static_cast<int>(rng() % 2), false});
    AgainstExact c;
    ASSERT_NO_FATAL_FAILURE(CompareWithExact(devs, testing::ExclusionForm::kAtMostTwo, 16, 16, c));
    EXPECT_LE(c.bound, c.optimum) << "THE TWO-MACHINE BOUND IS ABOVE THE OPTIMUM, case " << i << ": "
                                  << c.plan;
    bites += c.bound > c.others;
  }
  EXPECT_GE(bites, 1) << "the two-machine bound never rose above the others";
}

}  // namespace
}  // namespace ctb
