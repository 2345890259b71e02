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

#include "planner/model/domain.h"
#include "planner/model/state_plan.h"

namespace ctb {

// nullopt when the relaxation has no plan (then no plan exists; the static checks report it).
std::optional<long> RelaxedCostBound(const Domain& d, const StatePlan& sp);

}  // namespace ctb
