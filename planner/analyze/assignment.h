// The assignment bound: a lower bound on when a condition read on one stage can first hold, for
// conditions whose clauses (clauses.h) let several automata serve them, e.g. "every person
// rescued by some robot".
//
// At the stage the condition holds, each automaton a is in one location l and serves the clauses
// that hold (a, l); it entered l no earlier than arrival[a][l] (earliest.h). So at a time T, each
// clause is served by an automaton that has some fact of the clause with arrival <= T, and an
// automaton serves at most cap_T(a) clauses: the most clauses one of its locations reached by T
// appears in. The least T at which such a flow from clauses to automata exists (a bipartite
// matching with capacities, tried at each distinct arrival time by bisection; feasibility only
// grows with T) is a lower bound. With one fact per automaton and clause (each robot serves one
// person) it is the bottleneck assignment: the slowest robot still has to rescue someone.
// Depends on the model only; thread-safe.
#pragma once

#include <optional>
#include <utility>
#include <vector>

#include "planner/analyze/clauses.h"

namespace ctb {

// The bound in the unit of `arrival` (ticks or events; values >= never are unreachable); 0 when
// there are no clauses or no time at which the flow exists (nothing is claimed then).
long AssignmentBound(const Clauses& clauses, const std::vector<std::vector<long>>& arrival,
                     long never);

// A row's choices: (column, cost >= 0); a column listed twice keeps its cheaper cost.
using AssignmentRow = std::vector<std::pair<int, long>>;

// The least total cost of giving every row a column of its own (columns in [0, columns); a column
// may stay unused): successive shortest augmenting paths with potentials (the Hungarian method
// over sparse rows), each path searched from its row and stopped at the first free column, so a
// row with one free choice costs one step. nullopt when no such assignment exists. Work about
// rows x (edges log edges) at worst.
std::optional<long> MinCostAssignment(int columns, const std::vector<AssignmentRow>& rows);

}  // namespace ctb
