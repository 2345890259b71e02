// Internal to the solve library: the flexible side of an answer with a plan (contract section
// 13): `network`, `slack` and `controllability`, and the status when the plan is not of the kind
// of controllability asked for.
#pragma once

#include <optional>
#include <vector>

#include "planner/flexible/flexible.h"
#include "planner/model/domain.h"
#include "planner/model/json_io.h"
#include "planner/model/state_plan.h"
#include "planner/model/trajectory.h"
#include "planner/solve/solve.h"

namespace ctb::solve {

// What the check of a plan's network found, for the search among plans (controllable.cpp).
struct FlexibleOutcome {
  std::optional<flexible::FlexiblePlan> plan;  // nullopt: no network (the resolution)
  std::vector<int> conflict;                   // links, when not dynamically controllable
  bool met = true;                             // of the asked kind (or accepted at the risk bound)
};

// `d` is the domain as written (contingent transitions marked); `plan` the answer's verified plan.
FlexibleOutcome AddFlexibility(SolveResult& answer, const Trajectory& plan, const Domain& d,
                               const StatePlan& sp, const SolveOptions& o);

// The kind of plan asked for, kAuto resolved by the domain.
Controllability Asked(const Domain& d, const SolveOptions& o);

}  // namespace ctb::solve
