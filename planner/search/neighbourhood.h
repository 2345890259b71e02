// Large-neighbourhood search on a verified plan (issue 29 item 3): the first-plan engine again,
// with most automata held to the transitions they take in the plan (FirstPlanOptions::scripts)
// and a few set free. Holding every automaton re-times the plan (the same transitions, fired as
// early as the rules allow: a team the plan sent out one after another goes out together);
// splices trade two automata's routes, or the starts of their routes, with every automaton held;
// freeing one, two or three automata lets them take other routes, swap tasks or take their turns
// in another order. Each round keeps only strictly better plans, which the verifier has passed;
// an improvement restarts the rounds from the new plan. Like the engine it proves nothing: a plan
// is optimal only when it meets a lower bound (analyze/bounds.h).
//
// Thread-safe: calls share nothing. Never throws.
#pragma once

#include <atomic>
#include <functional>
#include <optional>

#include "planner/model/domain.h"
#include "planner/model/state_plan.h"
#include "planner/model/trajectory.h"

namespace ctb {

struct NeighbourhoodOptions {
  Objective objective = Objective::kMakespan;
  long time_limit_ms = 500;  // all rounds (each gets a share: a 24th, at least 10 ms)
  // States a round may expand (FirstPlanOptions::max_expanded; 0: no limit): with a budget long
  // enough, the rounds' results no longer depend on the machine's speed (tests).
  long round_expansions = 0;
  int max_events = 32;
  const std::atomic<bool>* cancel = nullptr;
  // Stop at the first plan for which this returns true (it meets a proven lower bound).
  std::function<bool(long cost, long makespan_ticks)> good_enough;
  // Called with each strictly better verified plan, on the calling thread.
  std::function<void(const Trajectory&, long cost, long makespan_ticks)> on_plan;
};

struct NeighbourhoodResult {
  std::optional<Trajectory> best;  // strictly better than the plan given; verified
  long cost = 0;
  long makespan = 0;  // ticks
  int rounds = 0;     // engine runs
  int improved = 0;   // rounds that found a better plan
  long elapsed_ms = 0;
};

// Each automaton's transitions in `plan`, in event order (the scripts of FirstPlanOptions).
std::vector<std::vector<int>> TransitionsTaken(const Trajectory& plan, std::size_t automata);

// Improves `plan` (verified, with this cost and makespan in ticks, no history) within the budget.
NeighbourhoodResult ImproveByNeighbourhoods(const Domain& d, const StatePlan& sp,
                                            const Trajectory& plan, long cost, long makespan,
                                            const NeighbourhoodOptions& o);

}  // namespace ctb
