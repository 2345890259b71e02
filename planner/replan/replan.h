// Replanning during execution (contract section 11): from what happened up to `now` (the
// executed transitions, or the plan being executed up to `now`, overridden by observations) and
// the transitions reported blocked, the best future from `now`, judged with the history against
// the state plan as one run from e[0] = 0.
//
// "Could not run" (a bad request, located by JSON pointers relative to the request body:
// /executed/3/to, /observed/robot2/location, /blocked/0, /trajectory/transitions/2/from, /now) is
// an Error; "ran and answered" is a ReplanResult, written as the trajectory JSON of section 5 with
// the history's transitions marked "executed": true, observations that no transition explains as
// transitions marked "observed": true, `now`, and `diff` (the future's transitions against the previous plan's at or
// after now). Never throws. Thread-safe: calls share nothing. docs/replanning.md says what is
// assumed about the history and what `optimal` means.
#pragma once

#include <optional>
#include <variant>

#include "planner/model/domain.h"
#include "planner/model/error.h"
#include "planner/model/json_io.h"
#include "planner/model/state_plan.h"
#include "planner/solve/solve.h"

namespace ctb {

enum class Keep {
  kNone,       // any future
  kStarted,    // every automaton goes on with the transition the previous plan had it start
  kMinChange,  // among optimal futures, the fewest changes against the previous plan
};
const char* KeepName(Keep k);
std::optional<Keep> ParseKeep(const std::string& s);

// The request's fields, as JSON (the parts a client sends): read and checked by Replan.
struct ReplanRequest {
  Json now;                  // seconds (a number >= 0)
  Json executed;             // null: the previous plan's transitions before now are the history
  Json observed;             // null or {"<automaton>": {"location", "since"?}}
  Json blocked;              // null or [{"automaton", "from", "to"}]
  Json previous;             // the trajectory being executed (section 5); null when none
  std::string previous_pointer = "/trajectory";  // where `previous` sits in the request
};

struct ReplanOptions {
  // objective, time_limit_ms, max_horizon (the most events of the future), minizinc, search
  // (Gecode strategies; z3 has no history), cancel, on_progress. The horizon option is refused.
  SolveOptions solve;
  Keep keep = Keep::kNone;
  // Checks, before any solve, whether the history already broke a part of the state plan or the
  // blocked transitions cut the goal off (then `infeasible` at once). Off only in tests that
  // compare them with the solver.
  bool precheck = true;
};

// Reads a request body's replanning fields (now, executed, observed, blocked, trajectory, and
// options.keep into *keep when given). Unknown fields are the caller's business.
std::optional<Error> ReadReplanRequest(const Json& body, ReplanRequest& out, Keep* keep);

// A replan's answer: the solve's, whose plan begins with the history, and what replanning adds.
struct ReplanResult {
  SolveResult answer;
  long now_ticks = 0;
  Keep keep = Keep::kNone;
  // With a plan: the future's transitions against the previous plan's at or after now,
  // {"kept", "moved", "added", "dropped"}.
  std::optional<Json> diff;
};

// The answer as the contract's document: the trajectory (section 5) with `now`, `keep`, `diff`.
Json ReplanJson(const ReplanResult& r, const Domain& d, const StatePlan& sp);

std::variant<ReplanResult, Error> Replan(const Domain& d, const StatePlan& sp,
                                         const ReplanRequest& req, const ReplanOptions& o);

// Replan's answer written by ReplanJson, for local callers that want the document (tests, tools).
std::variant<Json, Error> ReplanDocument(const Domain& d, const StatePlan& sp,
                                         const ReplanRequest& req, const ReplanOptions& o);

// Checks the request against the domain and state plan as Replan does, without solving: every
// error at its pointer, or nullopt.
std::optional<Error> CheckReplanRequest(const Domain& d, const StatePlan& sp,
                                        const ReplanRequest& req);

}  // namespace ctb
