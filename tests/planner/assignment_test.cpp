// The assignment bound (planner/analyze/assignment.h): by hand, and on the mixed-speed team of
// bench/families.py, where it is the optimum.
#include "planner/analyze/assignment.h"

#include <gtest/gtest.h>

#include "planner/analyze/bounds.h"
#include "team_problem.h"

namespace ctb {
namespace {

constexpr long kNever = 1000;

TEST(AssignmentBound, TheSlowerAutomatonMustServeAClause) {
  // Two clauses, each servable by either automaton, in different locations.
  const Clauses c = {{{0, 1}, {1, 1}}, {{0, 2}, {1, 2}}};
  const std::vector<std::vector<long>> arrival = {{0, 5, 5}, {0, 9, 9}};
  EXPECT_EQ(AssignmentBound(c, arrival, kNever), 9);
}

TEST(AssignmentBound, OneLocationMayServeSeveralClauses) {
  // Automaton 0 in location 1 serves both clauses at once.
  const Clauses c = {{{0, 1}, {1, 1}}, {{0, 1}, {1, 2}}};
  const std::vector<std::vector<long>> arrival = {{0, 5, 5}, {0, 9, 9}};
  EXPECT_EQ(AssignmentBound(c, arrival, kNever), 5);
}

TEST(AssignmentBound, ClaimsNothingWithoutAFlow) {
  const std::vector<std::vector<long>> arrival = {{0, 5, kNever}, {0, kNever, 9}};
  // Both clauses need automaton 0 in different locations: no time works; nothing claimed.
  EXPECT_EQ(AssignmentBound({{{0, 1}}, {{0, 2}}}, arrival, kNever), 0);
  EXPECT_EQ(AssignmentBound({}, arrival, kNever), 0);
  EXPECT_EQ(AssignmentBound({Clause{}}, arrival, kNever), 0);
}

TEST(AssignmentBound, ProvesTheMixedSpeedTeamsOptimum) {
  for (int n : {3, 4, 8}) {
    testing::TeamProblem p = testing::MixedSpeedTeam(n);
    const ObjectiveBounds b = LowerBounds(p.domain, p.plan);
    EXPECT_EQ(b.makespan_ticks, 30) << n << " robots";  // the optimum (bench/results/families.md)
  }
  // Two robots: robot 2 (twice as slow) goes through the door robot 1 opens: 2 + 8 + 10.
  testing::TeamProblem two = testing::MixedSpeedTeam(2);
  EXPECT_EQ(LowerBounds(two.domain, two.plan).makespan_ticks, 20);
}

}  // namespace
}  // namespace ctb
