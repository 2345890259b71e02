// Internal to the solve library: the search among plans for one of the asked kind of
// controllability (contract section 13, docs/uncertainty.md "Searching among plans").
#pragma once

#include <functional>
#include <variant>

#include "planner/model/domain.h"
#include "planner/model/error.h"
#include "planner/model/json_io.h"
#include "planner/model/state_plan.h"
#include "planner/solve/solve.h"

namespace ctb::solve {

// Solves `sp` on the domain as written (the callback plans for its worst case).
using FixedSolve = std::function<std::variant<SolveResult, Error>(
    const Domain& d, const StatePlan& sp, const SolveOptions& o)>;

// Plans, checks the plan's network, and while it is not of the asked kind cuts the conflict
// (flexible/cut.h) and plans again: the first plan of the asked kind is the best such plan (cuts
// remove only plans that are not). When nothing is left: `infeasible` with every conflict learned
// and the relaxations that, planned again, give a plan of the asked kind.
std::variant<SolveResult, Error> SolveControllable(const Domain& d, const StatePlan& sp,
                                                   const SolveOptions& o, const FixedSolve& fixed);

}  // namespace ctb::solve
