// What a condition needs, as clauses over location facts: a conjunction of clauses, each a
// disjunction of positive location atoms "automaton a is in location l" (a conjunctive normal
// form keeping only those atoms). A clause with any other literal (a negation, a command, an
// accepting state, a fixed stage) counts as satisfied: needing less is a relaxation, so whatever
// a run satisfies, it satisfies every clause. "robot1 in r1 or robot2 in r1" is one clause of two
// facts, where the conjunction-only reading (RequiredLocations, earliest.h) needs nothing.
// Read by the first-plan engine's heuristic (planner/search) and the assignment bound
// (assignment.h). Depends on the expression language only; thread-safe.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "planner/expr/expr.h"

namespace ctb {

using LocationAtom = std::pair<int, int>;  // (automaton, location)
using Clause = std::vector<LocationAtom>;  // a disjunction; empty: false
using Clauses = std::vector<Clause>;       // a conjunction; empty: true

// Beyond this many clauses (the product of a disjunction of conjunctions grows fast) only the
// first are kept: a subset of the clauses is still implied.
inline constexpr std::size_t kMaxClauses = 512;
// A conjunction keeps up to this many: a team's goal has one clause a member (every(k in robot:
// ...) over 1,000 robots: 1,000 clauses; capped at 512, the first-plan engine's heuristic saw the
// goal of 640 robots met with 128 still out). Twice the most automata a domain may have; the
// readers' work (the assignment bound's matching, the heuristic's choice of facts) stays bounded.
inline constexpr std::size_t kMaxConjunctionClauses = 4096;

// The clauses of a checked expression.
Clauses ToClauses(const Expr& e);

}  // namespace ctb
