// What a solve answers, typed (contract section 5): how it ended, the verified plan, its value
// and the bound, how far a proof of infeasibility reaches, and who found and who proved it.
// ResultJson writes it as the contract's trajectory document, once, where it leaves the process
// (HTTP, SSE, the CLI); the gRPC front end and the application core read the fields.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "planner/model/domain.h"
#include "planner/model/json_io.h"
#include "planner/model/objective_value.h"
#include "planner/model/state_plan.h"
#include "planner/model/trajectory.h"

namespace ctb {

enum class Termination { kOptimal, kFeasible, kInfeasible, kUnknown };
const char* TerminationName(Termination t);  // "optimal" | "feasible" | "infeasible" | "unknown"
inline bool Proven(Termination t) { return t == Termination::kOptimal || t == Termination::kInfeasible; }

// How far a proof of infeasibility reaches: up to the solve's max_horizon events (a solver's
// proof), or whatever the number of events (static analysis, a history that already broke the
// state plan).
enum class InfeasibleScope { kNone, kMaxHorizon, kAnyHorizon };
const char* InfeasibleScopeName(InfeasibleScope s);  // "" | "max_horizon" | "any_horizon"

// Why a state plan has no plan (contract section 9, `explanation`; planner/explain/explain.h
// says how each is found).
struct ExplanationConflict {
  std::vector<std::string> constraints;  // the state plan's parts, as pointers
  std::string text;
  Json broken_at;  // replanning: when the history broke it (seconds); null otherwise
};
struct ExplanationRelaxation {
  Json changes;  // [{"pointer", "value"}]: a bound's new value, or null to drop the part
  std::string text;
};
enum class ExplanationStatus {
  kMinimal,          // every proper subset of the conflict is feasible
  kUnknown,          // the budget ended first: `consistent` is the largest set shown feasible
  kControllability,  // no plan of the asked kind of controllability (contract section 13)
};
struct Explanation {
  std::vector<ExplanationConflict> conflicts;
  std::vector<ExplanationRelaxation> relaxations;
  ExplanationStatus status = ExplanationStatus::kUnknown;
  std::optional<std::vector<std::string>> consistent;
  Json stats;         // solver_calls, ms, conflict_by, conflict_ms, z3_checks; null: none
  std::string error;  // what stopped the explainer, when something did
};
const char* ExplanationStatusName(ExplanationStatus s);  // "minimal" | "unknown" | "controllability"
Json ExplanationJson(const Explanation& e);

// What found a plan or proved a status: an exact engine (named by its backend: "gecode", "z3",
// or a test's own), or one of the planner's own methods.
enum class Method {
  kNone, kEngine, kHeuristic, kLowerBound, kStaticAnalysis, kHistoryCheck,
  kZoneSearch,  // the makespan bound raised by the zone search with a deadline (bounds.h)
};
struct Credit {
  Method method = Method::kNone;
  std::string engine;  // kEngine: the backend's name
  // "gecode", "heuristic", "lower bound", "static analysis", "history check", "zone search";
  // "" for kNone.
  std::string Name() const;
  bool empty() const { return method == Method::kNone; }
};
inline Credit ByEngine(std::string name) { return {Method::kEngine, std::move(name)}; }

struct SolveStats {
  // The engine(s) that ran ("gecode", "z3", "gecode+z3", "static analysis", "history check").
  std::string solver;
  Credit found_by;   // what found the plan kept; none without a plan
  Credit proved_by;  // what proved the status; none unless proven
  long compile_ms = 0;
  long solve_ms = 0;
  long first_solution_ms = -1;
  long variables = 0;
  int solver_runs = 0;
  // What particular steps add, by name (parts, static_conflict, heuristic, history_events, ...).
  Json extra = Json::object();
};

struct SolveResult {
  Termination status = Termination::kUnknown;
  Objective objective = Objective::kCost;
  long ticks_per_second = 1;
  std::optional<Trajectory> plan;  // the verified plan; none when no plan was found
  long cost = 0;                   // the plan's transition costs (with a plan)
  long makespan_ticks = 0;         // when the plan reaches its goal (with a plan)
  std::optional<ObjectiveValue> bound;  // feasible: what no plan beats
  int horizon = 0;                 // without a plan: the events of the last model tried
  int max_horizon = 0;
  InfeasibleScope scope = InfeasibleScope::kNone;
  std::string message;             // why the answer is not what was asked (contract 13), or ""
  SolveStats stats;
  // Contract 13, for a plan whose network was derived: `network` (null when the plan has none),
  // `slack` and `controllability`, as their documents.
  std::optional<Json> network, slack, controllability;
  // Added after the solve by those who explain it (planner/explain): `state_plan_summary` and,
  // when infeasible, `explanation`.
  std::optional<Json> summary;
  std::optional<Explanation> explanation;

  bool verified() const { return plan.has_value(); }
  // The plan's value in the objective's shape; nullopt without a plan.
  std::optional<ObjectiveValue> Value() const;
};

// The answer's "objective": {"kind", "value"}, the value null without a plan.
Json ObjectiveJson(const SolveResult& r);

// The contract's trajectory document (section 5, with sections 9 and 13's members).
Json ResultJson(const SolveResult& r, const Domain& d, const StatePlan& sp);

}  // namespace ctb
