// A cost lower bound from the delete relaxation of the automata (issue 9): facts "automaton a
// has been in location l", one action per transition and per alternative of its guard (the
// positive location atoms it needs; commands and negative atoms are dropped), and a goal made of
// the locations the end state pins (each alternative of a disjunctive goal) and those the
// episodes and temporal constraints need. Every plan is a relaxed plan, so the relaxed optimum
// is at most its cost; the LM-cut heuristic (Helmert and Domshlak, 2009) bounds that optimum
// from below. Unlike the per-automaton graph bound of analyze/bounds.h it counts the help other
// automata must give (someone opens the door, and the door moves), shared once.
#pragma once

#include <optional>
#include <utility>
#include <vector>

#include "planner/model/domain.h"
#include "planner/model/state_plan.h"

namespace ctb {

// nullopt when the relaxation has no plan (then no plan exists; the static checks report it).
std::optional<long> RelaxedCostBound(const Domain& d, const StatePlan& sp);

// The same for the assignment cost bound (analyze/assignment_cost.h): the transitions of the
// automata marked in `free_automata` (indexed by automaton) cost nothing, so the bound is on what
// the other automata's transitions cost; and the goal is also read as clauses.
std::optional<long> RelaxedCostOfOthers(const Domain& d, const StatePlan& sp,
                                        const std::vector<char>& free_automata);

// False when the relaxation (the goal also read as clauses) cannot reach its goal without entering
// any of `facts` ((automaton, location) pairs): then every plan enters one of them or starts in
// one (a disjunctive landmark: some robot must stand where a door opens).
bool RelaxedReachableAvoiding(const Domain& d, const StatePlan& sp,
                              const std::vector<std::pair<int, int>>& facts);

}  // namespace ctb
