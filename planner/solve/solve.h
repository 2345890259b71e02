// Solving a state-planning problem end to end: horizon search, MiniZinc + Gecode, extraction,
// independent verification (contract sections 2, 3, 5).
//
// "Could not run" (bad options, a solver failure, a trajectory that fails verification) is an
// Error; "ran and answered" is a SolveResult (solve_result.h) whose status is optimal, feasible,
// infeasible or unknown. Never throws. Thread-safe: calls share nothing.
#pragma once

#include <atomic>
#include <memory>
#include <functional>
#include <optional>
#include <string>
#include <variant>

#include "planner/model/domain.h"
#include "planner/model/error.h"
#include "planner/model/state_plan.h"
#include "planner/model/trajectory.h"
#include "planner/analyze/bounds.h"
#include "planner/solve/solve_result.h"

namespace ctb {

class SolverBackend;

constexpr int kMaxHorizonLimit = 200;
// Gecode's integer variables hold at most this (Gecode::Int::Limits::max).
constexpr long kSolverIntMax = 2147483646;

enum class Controllability { kAuto, kDynamic, kStrong, kNone };
const char* ControllabilityName(Controllability c);  // "auto" | "dynamic" | "strong" | "none"
std::optional<Controllability> ParseControllability(const std::string& s);

// An improving verified plan, as the solve keeps it (SolveOptions::on_progress).
struct SolveProgress {
  ObjectiveValue value;  // the plan's cost and makespan, in the solve's objective kind
  ObjectiveValue bound;  // what no plan can beat (the same kind)
  int horizon = 0;       // the plan's events
  long elapsed_ms = 0;   // since the solve began
  Credit found_by;       // what found it: the heuristic or an engine
};

struct SolveOptions {
  std::optional<Objective> objective;  // overrides the state plan's
  std::optional<int> horizon;          // a fixed number of events
  int max_horizon = 32;                // the most events tried (horizon growth)
  long time_limit_ms = 60000;          // for the whole solve
  std::string minizinc = "minizinc";
  int threads = 1;
  long memory_limit_mb = 0;            // each solver process's address-space ceiling (0: none)
  bool decompose = true;               // solve independent parts separately and merge
  bool reuse_identical_parts = true;   // parts whose encodings are equal are solved once
  bool redundant = true;               // the encoder's redundant constraints (bench only)
  // Interchangeable automata (analyze/symmetry.h) ordered in the Gecode models (EncodeOptions::
  // symmetry); never with a history. Off only to measure it or to check it (tests, bench/).
  bool symmetry = true;
  // "portfolio" runs the first `portfolio` of g_first, tc_first (Gecode) and z3 at once (one
  // core each) and keeps the first proof; or one strategy: g_first, tc_first, first_fail,
  // transitions_first, default (Gecode's own), or z3 (the z3 engine alone, planner/smt).
  std::string search = "portfolio";
  int portfolio = 2;
  long portfolio_delay_ms = 300;       // the second strategy starts only after this
  std::string model_out;               // when set, the last model is written here (+ .json data)
  // Local callers (tests, benchmarks, the CLI's simulator): receives the answer's plan, typed,
  // when the answer has one. Not owned.
  Trajectory* plan_out = nullptr;
  // Contingent transitions (contract section 13): the kind of plan asked for. kAuto: dynamic
  // where the domain has contingent transitions. kNone plans as if the planner picked every
  // duration; the others plan for the worst case (every contingent duration at its longest) and
  // report whether the plan's network is strongly and dynamically controllable.
  Controllability controllability = Controllability::kAuto;
  // The answer's network, slack and controllability (contract section 13). Off for the probes
  // of a state plan's parts (the explainer), whose answers are never shown.
  bool derive_network = true;
  // Accept a plan that is not of the asked kind when its estimated failure probability (under
  // the contingent transitions' distributions, dispatched at its times) is at most this.
  std::optional<double> risk_bound;
  // The search among plans (solve/controllable.h): at most this many plans that are not of the
  // asked kind are cut before the answer is the first plan found, unknown. 0: no search.
  int max_plan_cuts = 16;
  const std::atomic<bool>* cancel = nullptr;
  // The engine that solves each model; nullptr: MiniZinc with Gecode (backend.h). Not owned.
  SolverBackend* backend = nullptr;
  // Static checks that prove infeasibility without search (planner/analyze) run first.
  bool static_analysis = true;
  // The first-plan engine (planner/search) runs next for at most this long: its verified plan is
  // streamed first and handed to the exact engines as the incumbent. When that plan does not meet
  // the lower bound, the neighbourhood search (planner/search/neighbourhood.h) improves it for as
  // long again (within the time limit). -1: min(500 ms, a tenth of time_limit_ms); 0: neither runs.
  long first_plan_ms = -1;
  // Makespan, when the first-plan engine's plan does not meet the lower bound: the zone search
  // with a deadline (analyze/bounds.h, RaiseMakespanBound) tries for at most this long to show
  // that no plan ends earlier, or raises the bound. -1: min(2000 ms, a fifth of time_limit_ms);
  // 0: off.
  long zone_proof_ms = -1;
  // Internal (the split's lower bounds): runs whose events may carry no transition.
  bool idle_events = false;
  // Called on the calling thread each time a better verified plan is kept. Not called for the
  // parts of a decomposed problem (their objectives are not the whole plan's).
  std::function<void(const SolveProgress& progress)> on_progress;
  // Replanning (planner/replan): the run begins with this fixed history (the encoder's and the
  // verifier's `history`), and `bounds`, valid given it, replace those computed from the initial
  // state. The first-plan engine starts from the history (but declines keep "started"); of the
  // exact engines Gecode only (z3 has no history); no static analysis or split applies.
  std::shared_ptr<const History> history;
  std::optional<ObjectiveBounds> bounds;
  // Where horizon growth starts when larger than the event bound (replanning: the previous
  // plan's number of events). Sound at any value: a model holds every smaller plan.
  int first_horizon = 0;
};

// The lower bounds a solve computes (analyze/bounds.h): the assignment bound on cost only when the
// objective reads cost (a makespan solve never does).
inline BoundOptions CostBoundsFor(Objective objective) {
  return {.assignment_cost = objective != Objective::kMakespan,
          .least_cost_makespan = objective == Objective::kCostThenMakespan};
}

// Checks the options themselves (ranges); errors carry the option's name as pointer.
std::optional<Error> ValidateSolveOptions(const SolveOptions& o);

// The time bound and the objective at max_horizon must fit the solver's integers; an Error
// (kInvalidInput) names the transition or bound that makes them too large.
std::optional<Error> CheckRepresentable(const Domain& d, const StatePlan& sp, Objective objective,
                                        int max_horizon);

// The answer, typed, or an Error.
std::variant<SolveResult, Error> Solve(const Domain& d, const StatePlan& sp, const SolveOptions& o);

// Solve's answer written as the contract's document (ResultJson), for local callers that want
// the JSON itself (tests, tools).
std::variant<Json, Error> SolveDocument(const Domain& d, const StatePlan& sp, const SolveOptions& o);

}  // namespace ctb
