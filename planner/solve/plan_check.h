// Whether a plan for one state plan is also a plan for another (ctburton eval's equivalence,
// contract section 15): the plan's run is fixed as a history of all its events and the solver
// places the other state plan's episodes, temporal constraints and orders on it, with the goal
// at the plan's last event. The same encoder and verifier as every answer: no second semantics.
#pragma once

#include "planner/model/trajectory.h"
#include "planner/solve/solve.h"

namespace ctb {

enum class PlanCheck { kValid, kInvalid, kUnknown };
const char* PlanCheckName(PlanCheck c);  // "valid" | "invalid" | "unknown"

// t: a verified run of d (times in d's ticks). `base` gives the solver's settings (minizinc,
// time limit, cancel); its horizon, history and objective are replaced. kUnknown when the solver
// was cut off or failed.
PlanCheck CheckPlanAgainst(const Trajectory& t, const Domain& d, const StatePlan& sp,
                           const SolveOptions& base);

// The history of a whole run: every event of t fixed, entry times from its transitions.
std::shared_ptr<History> HistoryOfRun(const Trajectory& t, std::size_t automata);

}  // namespace ctb
