// Internal to the solve library: the flexible side of an answer with a plan (contract section
// 13): `network`, `slack` and `controllability`, and the status when the plan is not of the kind
// of controllability asked for.
#pragma once

#include "planner/model/domain.h"
#include "planner/model/json_io.h"
#include "planner/model/state_plan.h"
#include "planner/model/trajectory.h"
#include "planner/solve/solve.h"

namespace ctb::solve {

// `d` is the domain as written (contingent transitions marked); `plan` the answer's verified plan.
void AddFlexibility(Json& answer, const Trajectory& plan, const Domain& d, const StatePlan& sp,
                    const SolveOptions& o);

}  // namespace ctb::solve
