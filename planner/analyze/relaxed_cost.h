// A cost lower bound from the delete relaxation of the automata (issue 9): facts "automaton a
// has been in location l", one action per transition and per alternative of its guard (the
// positive location atoms it needs; commands and negative atoms are dropped), and a goal made of
// the locations the end state pins (each alternative of a disjunctive goal) and those the
// episodes and temporal constraints need. Every plan is a relaxed plan, so the relaxed optimum
// is at most its cost; the LM-cut heuristic (Helmert and Domshlak, 2009) bounds that optimum
// from below. The goal is read both as alternatives (a disjunctive form, capped) and as clauses
// (analyze/clauses.h: "every person rescued by some robot" stays n clauses where its
// alternatives number n^n). Unlike the per-automaton graph bound of analyze/bounds.h it counts the help other
// automata must give (someone opens the door, and the door moves), shared once.
#pragma once

#include <optional>
#include <utility>
#include <vector>

#include "planner/model/domain.h"
#include "planner/model/state_plan.h"

namespace ctb {

// nullopt when the relaxation has no plan (then no plan exists; the static checks report it).
// With `free_automata` (indexed by automaton; empty: none), the transitions of the automata marked
// there cost nothing: the bound is then on what the other automata's transitions cost (the
// assignment cost bound, analyze/assignment_cost.h, bounds the marked ones apart).
std::optional<long> RelaxedCostBound(const Domain& d, const StatePlan& sp,
                                     const std::vector<char>& free_automata = {});

// False when the relaxation cannot reach its goal without entering any of `facts` ((automaton,
// location) pairs): then every plan enters one of them or starts in one (a disjunctive landmark:
// some robot must stand where a door opens).
bool RelaxedReachableAvoiding(const Domain& d, const StatePlan& sp,
                              const std::vector<std::pair<int, int>>& facts);

}  // namespace ctb
