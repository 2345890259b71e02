// Internal to the search library: the choice of one fact per clause of a condition
// (analyze/clauses.h) that the relaxed plan (relaxed_plan.h) then supports.
//
// A condition on one stage (not a change) is read where each automaton is in one location: the
// choice never puts one automaton in two locations while a consistent fact is left (which robot
// rescues whom: each robot serves one person).
#pragma once

#include <functional>
#include <vector>

#include "planner/analyze/clauses.h"

namespace ctb::search {

// One fact per clause, cheapest first: the clause/fact pairs in order of `cost` (ties: clause
// order, then the fact's order in its clause), a pair taken when its clause is not yet satisfied
// and, with one_stage, its automaton has no other location chosen; a chosen fact satisfies every
// clause that holds it. A clause left with nothing consistent takes its cheapest fact. `cost` is
// +infinity for a fact not reachable. Appends the chosen facts to out, each once, in the order of
// the clauses that got them (a plain conjunction: its atoms in order); returns false (out
// unchanged) when every fact of some clause is unreachable.
bool ChooseFacts(const Clauses& clauses, bool one_stage,
                 const std::function<double(const LocationAtom&)>& cost,
                 std::vector<LocationAtom>& out);

}  // namespace ctb::search
