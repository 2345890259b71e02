// The assignment bound on cost (issue 29 item 2): a lower bound on what a plan costs when the goal
// (read on one stage) lets several automata serve its clauses (clauses.h), e.g. "every person
// rescued by some robot" with robots of different running costs.
//
// Costs add up over automata, so the bound is a part for the automata the goal's clauses name (S)
// plus a part for the others, each counting transitions the other does not:
// - S: at the goal stage each automaton a of S is in one location l, and its run cost at least
//   need_a(l), its cheapest way (guards ignored) from its initial location through every location
//   it must visit (`visits`, bounds.cpp) to l; an automaton asked for nothing costs at least
//   need_a(-), its cheapest way through its visits. Take clauses whose facts are pairwise distinct
//   (no (a, l) in two of them; the shorter clauses kept first): an automaton in one location
//   serves at most one of them, so they are served by distinct automata, and S costs at least
//   sum_a need_a(-) plus a minimum-cost assignment (MinCostAssignment, assignment.h) of those
//   clauses to automata at need_a(l) - need_a(-). Clauses left out only weaken the bound: every
//   plan still meets the ones kept.
// - help (a disjunctive landmark): when the relaxation (relaxed_cost.h) cannot reach the goal
//   without one of the facts of S that another automaton's guards read (a robot where a door
//   opens), every plan has some a of S enter one such (a, v), so a's run passes through v. The S
//   part is then the least, over those facts, of the assignment with a's costs through v.
// - the others: at least their own cheapest ways (`own_cost`, bounds.cpp) and at least the
//   relaxation's bound with the transitions of S free (LM-cut, relaxed_cost.h).
// Depends on the model only; thread-safe.
#pragma once

#include <utility>
#include <vector>

#include "planner/model/domain.h"
#include "planner/model/state_plan.h"

namespace ctb {

// 0 when nothing is claimed: a goal that describes a change, no clause, no choice (every clause
// one fact: the graph bound and the relaxation see that), or no assignment (then no plan exists;
// the static checks and the exact engines say so). `visits[a]`: the locations
// automaton a must enter (episodes, temporal constraints, guard landmarks); `own_cost[a]`: a
// bound on what automaton a's transitions cost in every plan. `known`: a cost bound already
// proven; the help landmark (one assignment per fact) is tried only when it could end above it.
long AssignmentCostBound(const Domain& d, const StatePlan& sp,
                         const std::vector<std::vector<int>>& visits,
                         const std::vector<long>& own_cost, long known = 0);

// What plans costing at most `budget` can reach, for the makespan bound of plans of least cost
// (bounds.h, cost_then_makespan):
// - `costly`: locations (automaton, location) no such plan enters: with the automaton's cheapest
//   way through the location (`final_loc[a]`: where the goal pins it, or -1), the others' own
//   ways (`own_cost`) add up to more than the budget; or, for an automaton of S, the assignment
//   with its costs through the location plus the others' part does;
// - `bottleneck`: the least time t such that an assignment of the distinct clauses to automata
//   that can arrive by t (`arrival[a][l]`, ticks: analyze/earliest.h) keeps S's cost plus the
//   others' within the budget; 0 when nothing is claimed or without `arrival`.
// Work is capped (a shorter cut list and a 0 bottleneck are never wrong, only weaker).
struct WithinBudget {
  std::vector<std::pair<int, int>> costly;
  long bottleneck = 0;
};
WithinBudget ReachWithinBudget(const Domain& d, const StatePlan& sp,
                               const std::vector<std::vector<int>>& visits,
                               const std::vector<long>& own_cost, const std::vector<int>& final_loc,
                               const std::vector<std::vector<long>>* arrival, long budget);

}  // namespace ctb
