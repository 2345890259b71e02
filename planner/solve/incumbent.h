// Internal to the solve library: the first-plan engine (planner/search) as the first stage of a
// solve. Its plan is checked by the independent verifier here too, streamed through on_progress
// and handed to the exact engines as the incumbent (docs/encoding.md, "The first-plan engine").
#pragma once

#include <optional>

#include "planner/analyze/bounds.h"
#include "planner/solve/horizon_solver.h"

namespace ctb::solve {

// The budget: SolveOptions::first_plan_ms, or min(500 ms, a tenth of the time limit) for -1.
long FirstPlanBudgetMs(const SolveOptions& o);

// Runs the engine for its budget, then, when its plan does not meet the bounds and there is no
// history, the neighbourhood search on it for as long again (within the time limit); returns the
// best verified plan with at most max_events events and records what they did in
// stats["first_plan"] (ms, expanded, generated, found, declined) and stats["neighbourhoods"] (ms,
// rounds, improved). `found_ms` is the time (since t0) the returned plan was found.
// `bounds` (LowerBounds(d, sp), or with a history SolveOptions::bounds, valid given it) stops
// the search at a plan that meets them. With o.history the engine starts from the history and
// its plans carry it (the verifier checks them as it checks the exact engines').
std::optional<Plan> FirstPlanIncumbent(const Domain& d, const StatePlan& sp, const SolveOptions& o,
                                       Objective objective, int max_events,
                                       const ObjectiveBounds& bounds, Clock::time_point t0,
                                       Json& stats, long& found_ms);

}  // namespace ctb::solve
