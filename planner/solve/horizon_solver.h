// Internal to the solve library: one model's horizon growth and optimality closing.
#pragma once

#include <chrono>
#include <optional>
#include <string>

#include "planner/model/elapsed.h"
#include "planner/model/trajectory.h"
#include "planner/solve/solve.h"

namespace ctb::solve {

using Clock = std::chrono::steady_clock;


struct Plan {
  Trajectory traj;
  long cost = 0;
  long makespan = 0;  // ticks
};

// What one solve found, before it is turned into the answer JSON.
struct Core {
  Termination status = Termination::kUnknown;
  std::optional<Plan> best;
  int horizon = 0;
  int runs = 0;
  long compile_ms = 0;
  long variables = 0;
  long first_solution_ms = -1;
  // The engine(s) whose runs decided the answer ("gecode", "z3", "gecode+z3"); empty: none ran.
  std::string engine;
  // What found the plan kept (the heuristic, an engine), and what proved the status when it is
  // optimal or infeasible (an engine, the lower bound, static analysis); none when unknown (then
  // the answer credits `engine`).
  Credit found_by;
  Credit proved_by;
  std::optional<Error> error;
};

// Adds an engine's name to a "+"-separated list of names, once.
void AddEngine(std::string& engines, const std::string& name);

enum class Refutation { kRefuted, kBetterExists, kUnknown };

// Grows the horizon until a plan exists, solves it to optimality and closes optimality over
// every plan with at most max_horizon events (docs/encoding.md). Errors go to Core::error.
// With an incumbent (a verified plan with at most max_horizon events, e.g. the first-plan
// engine's), every model asks only for a strictly better plan, and "none at any horizon" proves
// the incumbent optimal.
Core SolveOneModel(const Domain& d, const StatePlan& sp, const SolveOptions& o,
                   const std::optional<Plan>& incumbent = std::nullopt);

// Proves that no plan strictly better than `than` exists (at most max_horizon events, or
// exactly the fixed horizon), or finds one; stats (runs, times) and any error go to `stats`.
Refutation RefuteBetter(const Domain& d, const StatePlan& sp, const SolveOptions& o,
                        const Plan& than, Core& stats);

// True when a is strictly better than b for the objective.
bool BetterPlan(Objective objective, const Plan& a, const Plan& b);

}  // namespace ctb::solve
