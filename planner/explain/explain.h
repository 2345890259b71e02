// Why a state plan is infeasible and how to make it feasible (contract section 9,
// `explanation`), and the fields every answer carries (`state_plan_summary`).
//
// The explanation of an infeasible plan:
//   {"conflicts": [{"constraints": [pointer...], "text"}],
//    "relaxations": [{"changes": [{"pointer", "value"}], "text"}],
//    "status": "minimal" | "unknown", "consistent"?: [pointer...], "stats": {...}}
// The conflict is a minimal set of parts (goal, maintenance constraint, episodes, temporal
// constraints, shared events) that cannot hold together: every proper subset is feasible. It is
// found by static analysis (planner/analyze) when that proves infeasibility; else it is a
// minimised unsatisfiable core of the z3 model at the solve's horizon, with an assumption
// literal per part (planner/smt/z3_core.h), and when z3 does not finish in half the remaining
// time, a deletion filter over solver calls on reduced state plans goes on from the core
// reached. Before either, a quick pass checks each set without one part with a short limit
// (plans come fast, proofs do not). Static analysis is tried on every reduced plan before a
// solver (none at all when the SolveOptions turn `static_analysis` off). Dropping a part means: a goal or maintenance constraint becomes `true`; an episode or
// temporal constraint is removed with its endpoints in shared events (a shared event left with
// fewer than two endpoints goes too). A part that other parts' conditions name cannot be
// dropped alone and stays in the set.
// Each relaxation is checked by solving the whole plan with it applied: a bound moved by the
// least amount that makes the plan feasible (binary search between the bound and a witness plan
// found with the bound dropped; the static bound first; each check limited to
// relaxation_check_ms, each search to relaxation_search_ms, and the text says when a smaller
// value may work too), or `null` to drop a part; bound changes first, smallest relative change
// first, at most three.
// When the time budget ends before minimality is proven, `status` is "unknown", the conflict is
// the (infeasible, perhaps not minimal) set reached so far, and `consistent` lists the largest
// set of parts shown feasible together. `stats` says what found the conflict ("conflict_by":
// "static analysis", "z3 core" or "deletion filter") and when ("conflict_ms").
//
// Solver calls use the caller's options (horizon, max_horizon, minizinc, cancel) with the cost
// objective: feasibility does not depend on the objective. A check that needs no witness stops at
// the first verified plan (one model, one Gecode strategy, the first-plan engine first), and
// every set of parts shown feasible answers for its subsets, every set shown infeasible for its
// supersets (docs/explain.md). Never throws; thread-safe.
#pragma once

#include <optional>

#include "planner/model/domain.h"
#include "planner/model/json_io.h"
#include "planner/model/state_plan.h"
#include "planner/solve/solve.h"

namespace ctb {

struct ExplainOptions {
  long time_limit_ms = 30000;  // for every solver call of the explanation together
  int max_relaxations = 3;
  // When static analysis finds no conflict: a minimised unsatisfiable core from z3 (else the
  // deletion filter with Gecode).
  bool z3_cores = true;
  // Each solve that checks a relaxation stops after this long ("unknown": the bound search
  // keeps the least value shown to work and says a smaller one may work too).
  long relaxation_check_ms = 1000;
  // The binary search for one bound's least working value stops after this long.
  long relaxation_search_ms = 2000;
};

// The explanation of an infeasible plan (see above; ExplanationJson writes it). When the plan turns out feasible
// (which the caller should not ask), the conflicts are empty.
Explanation Explain(const Domain& d, const StatePlan& sp, const SolveOptions& so,
                    const ExplainOptions& eo = {});

// Adds the state plan's summary to an answer of Solve(), and the explanation when its status is
// infeasible (with a time budget equal to the solve's own time limit).
void AnnotateAnswer(const Domain& d, const StatePlan& sp, const SolveOptions& so,
                    SolveResult& answer);

// The explanation of an annotated answer in a few sentences for the LLM's next turn of a
// dialogue ("The planner found this impossible: ... Possible changes: ..."); "" when the answer
// has no explanation.
std::string DialogueNote(const SolveResult& answer);

// The state plan with `changes` applied ([{"pointer", "value"}], as in a relaxation: a number
// at a bound, or null to drop a part), checked again. nullopt with the errors in diags when a
// change does not apply or the result does not load.
std::optional<StatePlan> ApplyChanges(const Domain& d, const StatePlan& sp, const Json& changes,
                                      Diagnostics& diags);

}  // namespace ctb
