// Internal to the solve library: solving independent parts apart, soundly (docs/encoding.md,
// "Independent parts").
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "planner/solve/decompose.h"
#include "planner/solve/horizon_solver.h"

namespace ctb::solve {

// A canonical, horizon-independent text of a problem with every name replaced by its index:
// two parts with equal forms have the same plans, index for index.
std::string CanonicalForm(const Domain& d, const StatePlan& sp, Objective objective);

// Solves the parts (identical ones once), proves each part's optimum against relaxed runs in
// which another part's events may serve it, merges and verifies. nullopt: the split cannot be
// shown sound or the merge failed; solve the problem as one model.
std::optional<Core> SolveParts(const Domain& d, const StatePlan& sp,
                               const std::vector<SubProblem>& parts, const SolveOptions& o,
                               Objective objective, Clock::time_point t0, Json& stats);

}  // namespace ctb::solve
