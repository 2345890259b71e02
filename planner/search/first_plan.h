// The first-plan engine (issue 18): a heuristic forward search over the network of timed automata
// in time, as temporal planners do. It finds plans in milliseconds where the exact engines
// (MiniZinc + Gecode, z3) need a model per horizon, but proves nothing: a plan it returns is only
// `feasible` unless it meets a lower bound every plan obeys (analyze/bounds.h).
//
// States are the automata's locations, the clocks of their current locations (entry times) and
// the state plan's monitors (episodes started and ended with their times, the events of temporal
// constraints). Successors choose the commands of the current stage and the time of the next
// event, under the rules of the independent verifier (planner/verify), which is the semantics'
// reference: guards on the stage before, durations, automatic transitions due, commanded
// transitions that must fire, determinacy, concise runs, episodes from the first event their
// condition holds, temporal constraints, the first acceptance of the end state, the maintenance
// constraint. Every plan returned has passed VerifyTrajectory; one that does not is dropped.
//
// Greedy best-first search with deferred evaluation and preferred successors, guided by a
// relaxed-plan (FF) heuristic over the automata's location facts (costs are durations for
// makespan, transition costs otherwise), then, while time remains, the same search continues on
// g + h (the objective so far plus the estimate) and keeps only strictly better plans (anytime).
// Not complete: it may find no plan where one exists.
//
// Replanning (FirstPlanOptions::history): the run begins with the history's stages, taken as
// reported (planner/search/history_nodes.h), and the search plans the future from there, every
// event at or after `now`; the plan returned is the whole run, history included.
//
// Declines (no plan, `declined` set) state plans whose conditions read commands or fixed stages
// other than 0 (stage 0 is the initial state),
// state plans with shared events, and histories with keep "started" (History::keep_next).
// Thread-safe: calls share nothing. Never throws.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "planner/model/domain.h"
#include "planner/model/state_plan.h"
#include "planner/model/trajectory.h"

namespace ctb {

struct FirstPlanOptions {
  Objective objective = Objective::kCost;
  long time_limit_ms = 500;  // the whole search, improvements included
  // After the first plan (found at t ms) the search goes on for at most max(improve_min_ms,
  // t) more, within time_limit_ms: improvements are cheap near the first plan, rare later.
  // With good_enough set, until time_limit_ms (a plan that meets the bound spares a proof).
  long improve_min_ms = 20;
  int max_events = 32;       // plans with more events are not returned
  // The search stops after expanding this many states (0: no limit): a limit that does not
  // depend on the machine's speed.
  long max_expanded = 0;
  const std::atomic<bool>* cancel = nullptr;
  // Stop at the first verified plan for which this returns true (one that meets a proven lower
  // bound: no plan is better). Optional.
  std::function<bool(long cost, long makespan_ticks)> good_enough;
  // Called with each strictly better verified plan, on the calling thread.
  std::function<void(const Trajectory&, long cost, long makespan_ticks)> on_plan;
  // Replanning (planner/replan): the run begins with this history; null: from the initial state.
  // The cost and makespan of a plan are the whole run's (the history's cost included).
  std::shared_ptr<const History> history;
  // Large-neighbourhood search (issue 29 item 3, planner/search/neighbourhood.h): when not empty,
  // one entry per automaton, the transitions it must take in this order (nullopt: free to take
  // any). A run in which a scripted automaton takes another transition is not generated; a plan
  // may reach the goal before a script ends. Ignored with a history, or when its size is not the
  // number of automata.
  std::vector<std::optional<std::vector<int>>> scripts;
  // Optional, parallel to scripts: a rank per scripted transition (the plan's event of it). Held
  // automata that cannot all fire at once go in this order (the plan's order of turns).
  std::vector<std::vector<int>> script_ranks;
  // Only plans strictly better than this value (ObjectiveKey) are returned.
  std::optional<std::pair<long, long>> better_than;
};

// A plan's value as the engine compares it, lexicographically: (cost, 0), (makespan, 0) or
// (cost, makespan) by the objective.
std::pair<long, long> ObjectiveKey(Objective objective, long cost, long makespan);

struct FirstPlanResult {
  std::optional<Trajectory> best;  // verified; horizon = goal_event
  long cost = 0;
  long makespan = 0;               // ticks
  long expanded = 0;               // states expanded
  long generated = 0;
  long rejected = 0;               // plans the verifier refused (a bug in the engine if > 0)
  long elapsed_ms = 0;
  bool exhausted = false;          // the search space (as the engine sees it) was exhausted
  std::string declined;            // why the engine did not run; empty when it ran
};

FirstPlanResult FindFirstPlan(const Domain& d, const StatePlan& sp, const FirstPlanOptions& o);

}  // namespace ctb
