// Automata that take turns (planner/analyze/turns.h, issue 29 item 1): the one-machine bound on
// devices that warm up one at a time, by hand; against exact optima in turns_solve_test.cpp.
#include "planner/analyze/turns.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

#include "planner/analyze/bounds.h"
#include "turns_problem.h"

namespace ctb {
namespace {

using testing::Device;
using testing::ExclusionForm;
using testing::MakeTurns;

long Bound(const testing::TurnProblem& p) {
  auto e = ComputeEarliestTimes(p.domain, p.plan);
  return ComputeTurnBound(p.domain, p.plan, e ? &*e : nullptr).makespan_ticks;
}

long Ticks(const Domain& d, double s) { return std::lround(s / d.time_resolution); }

TEST(Turns, DevicesThatWarmUpOneAtATimeNeedTheSumOfTheirWarmUps) {
  for (int n = 2; n <= 6; ++n) {
    std::vector<Device> devs;
    int sum = 0;
    for (int k = 0; k < n; ++k) devs.push_back({0, 3 + (7 * k) % 5, 0, false}), sum += devs.back().warm;
    auto p = MakeTurns(devs);
    EXPECT_EQ(Bound(p), Ticks(p.domain, sum)) << n << " devices";
    // and LowerBounds takes it: each device alone needs only its own warm-up
    EXPECT_EQ(LowerBounds(p.domain, p.plan).makespan_ticks, Ticks(p.domain, sum)) << n << " devices";
  }
}

TEST(Turns, ReleasesAndTailsCount) {
  // dev1 may warm from 0 for 5 s; dev2 from 4 for 3 s and then needs 6 s more. Alone: 5 and 13;
  // in one order or the other the optimum is 13 (dev2 warms 4-7, dev1 7-12), which is the bound.
  auto p = MakeTurns({{0, 5, 0, false}, {4, 3, 6, false}});
  EXPECT_EQ(Bound(p), Ticks(p.domain, 13));
  // Both released at 2, each with a tail of 1: 2 + 4 + 4 + 1.
  auto q = MakeTurns({{2, 4, 1, false}, {2, 4, 1, false}});
  EXPECT_EQ(Bound(q), Ticks(q.domain, 11));
}

TEST(Turns, AVisitIsOneStay) {
  // Released at 0, 3 and 1, warm-ups of 3, 5 and 7, tails of 1, 3 and 5. Allowing a warm-up to be
  // interrupted, 16 would do (from 1: 5 + 7 = 12, plus the tail of 3); each warm-up is one stay,
  // and the best order (device 3 warms 1-8, device 2 8-13, device 1 13-16; ready at 13, 16, 17)
  // gives 17.
  auto p = MakeTurns({{0, 3, 1, false}, {3, 5, 3, false}, {1, 7, 5, false}});
  EXPECT_EQ(Bound(p), Ticks(p.domain, 17));
}

TEST(Turns, TheThreeWrittenFormsAreRead) {
  const std::vector<Device> devs = {{0, 2, 0, false}, {0, 3, 0, false}, {0, 4, 0, false}};
  for (auto form : {ExclusionForm::kNotBoth, ExclusionForm::kOrNot, ExclusionForm::kImplies}) {
    auto p = MakeTurns(devs, form);
    EXPECT_EQ(Bound(p), Ticks(p.domain, 9)) << static_cast<int>(form);
  }
}

TEST(Turns, NothingWhereTheTurnsAreNotForced) {
  // A device that may skip its warm-up takes no turn: only the other two count.
  auto p = MakeTurns({{0, 2, 0, false}, {0, 3, 0, false}, {0, 4, 0, true}});
  EXPECT_EQ(Bound(p), Ticks(p.domain, 5));
  // With one device left in turn, there is no machine.
  EXPECT_EQ(Bound(MakeTurns({{0, 2, 0, true}, {0, 3, 0, false}})), 0);
}

// At most two warm at once (no three together): no pair is excluded, but the three are two
// machines. Warm-ups of 2, 3 and 4 s: 9 s of work on two machines, at least 5 (4.5 rounded up to
// the tick), which is the optimum (2 then 3 beside 4).
TEST(Turns, AtMostTwoAtOnceAreTwoMachines) {
  const std::vector<Device> devs = {{0, 2, 0, false}, {0, 3, 0, false}, {0, 4, 0, false}};
  for (auto form : {ExclusionForm::kNotAllThree, ExclusionForm::kAtMostTwo, ExclusionForm::kAtMostTwoOr}) {
    auto p = MakeTurns(devs, form);
    EXPECT_EQ(Bound(p), Ticks(p.domain, 5)) << static_cast<int>(form);
  }
  // Four devices of 3, 4, 5 and 6 s, every three excluded: 18 s on two machines, 9.
  auto four = MakeTurns({{0, 3, 0, false}, {0, 4, 0, false}, {0, 5, 0, false}, {0, 6, 0, false}},
                        ExclusionForm::kAtMostTwo);
  EXPECT_EQ(Bound(four), Ticks(four.domain, 9));
  // The same written as consecutive triples only (1-2-3, 2-3-4): devices 1 and 4 may warm with
  // any two others, so no pool of four; each triple alone is two machines (12 / 2 and 15 / 2).
  auto consecutive = MakeTurns({{0, 3, 0, false}, {0, 4, 0, false}, {0, 5, 0, false}, {0, 6, 0, false}},
                               ExclusionForm::kNotAllThree);
  EXPECT_EQ(Bound(consecutive), Ticks(consecutive.domain, 8));
}

}  // namespace
}  // namespace ctb
