// An improving plan as the contract's `solution` event (section 9): {"kind", "objective" (in the
// kind's shape), "cost", "makespan", "horizon", "bound", "found_by", "elapsed_ms", "solve_ms"}.
// SSE sends it; gRPC maps its objective, bound and numbers. Apart from the core so that the gRPC
// conversions (and their fuzz target) need nothing else of app/.
#pragma once

#include "planner/solve/solve.h"

namespace ctb::app {

Json SolutionEventJson(const SolveProgress& p);

}  // namespace ctb::app
