// Lower bounds on the objective that hold for every plan (whatever its number of events), from
// the automata's graphs alone: used to close optimality without a solve at max_horizon when a
// plan meets them, and reported as `bound` when the time limit ends a search.
#pragma once

#include <atomic>
#include <utility>
#include <vector>

#include "planner/analyze/earliest.h"  // RequiredLocations
#include "planner/model/domain.h"
#include "planner/model/json_io.h"
#include "planner/model/objective_value.h"
#include "planner/model/state_plan.h"

namespace ctb {

struct ObjectiveBounds {
  long cost = 0;            // no plan costs less
  long makespan_ticks = 0;  // no plan reaches its goal earlier
  long events = 0;          // no plan accepts its end state at an earlier event
};

// Every automaton the goal pins to a location must at least take the cheapest (fastest) way there
// through each location an episode or temporal constraint needs it to visit (guards ignored);
// costs add up over automata, times do not; an episode lasts at least its lower bound after its
// location is first entered, and a temporal constraint's lower bound passes before the goal.
// Guards add visits (landmarks): when an automaton cannot reach a location it must enter without
// a transition whose guard needs another automaton in some location, that one must go there.
// The cost bound is also at least the delete relaxation's (analyze/relaxed_cost.h) and, for a goal
// whose clauses several automata may serve, the assignment of clauses to automata at their own
// costs (analyze/assignment_cost.h).
// The makespan bound is also at least the earliest goal time (analyze/earliest.h) and, for a goal
// on one stage that several automata may serve, the assignment bound (analyze/assignment.h). The event
// bound (the first horizon the search tries) counts each transition as an event of its own, and
// the earliest-times rules in events.
// The makespan bound is also at least the one-machine bound of locations the maintenance
// constraint keeps from being occupied at once (analyze/turns.h).
struct BoundOptions {
  // The assignment bound on cost (analyze/assignment_cost.h); off only to check it (tests).
  bool assignment_cost = true;
  // The turn-taking bound (analyze/turns.h); off only to check it (tests).
  bool turns = true;
  // cost_then_makespan: the makespan part bounds only the plans of the least cost the cost part
  // allows (a lexicographic bound): the same bounds on the model without the locations no plan of
  // that cost enters (analyze/assignment_cost.h, ReachWithinBudget). Not a bound on every plan's
  // makespan: set it for that objective only (solve.h, CostBoundsFor).
  bool least_cost_makespan = false;
  // Internal to that rule: the cost budget it reads (never below the cost bound of this call:
  // a cut at a lower budget would remove plans of the least cost) and how many times the model
  // has been cut for it (the cut model's arrival times give a later bottleneck, and may make more
  // locations too dear: the rule runs again on it, at most three cuts deep).
  long least_cost_budget = -1;
  int least_cost_cuts = 0;
};
ObjectiveBounds LowerBounds(const Domain& d, const StatePlan& sp, const BoundOptions& o = {});

// True when a plan of this cost and makespan meets the bounds (so no plan is better).
bool MeetsLowerBounds(const ObjectiveBounds& b, Objective objective, long cost, long makespan_ticks);

// A makespan bound raised by search (analyze/zone_bound.cpp): the zone search of zone_reach.h
// with a deadline, which follows every run of the automata and the state plan (time dense,
// commands read as either value), so "no run accepts the end state within D ticks" holds for
// every plan. Events are at whole ticks (as every plan's), and a state from which the rest of
// the run cannot end in time (analyze/earliest.h, RemainingTime) is not followed. Asks
// D = plan - 1 first (a proof that the plan is optimal), then bisects between the bound and the
// plan. Searched only for a state plan of a goal and a maintenance constraint
// (RemainingTime::Applies) and at most 8 automata; otherwise the bound is returned as given.
struct MakespanProofBudget {
  long ms = 0;            // wall time for all the searches together
  long states = 200000;   // symbolic states expanded, all searches together
  const std::atomic<bool>* cancel = nullptr;  // set: stop at once (no proof)
};
struct MakespanProof {
  long makespan_ticks = 0;  // no plan reaches its goal earlier (at least the bound given)
  int searches = 0;
  long states = 0;
  long ms = 0;
};
MakespanProof RaiseMakespanBound(const Domain& d, const StatePlan& sp, long bound_ticks,
                                 long plan_ticks, const MakespanProofBudget& budget);

// The bound in the shape of the answer's objective value: cost, makespan in seconds, or both.
ObjectiveValue BoundValue(const ObjectiveBounds& b, Objective objective, long ticks_per_second);
inline Json BoundJson(const ObjectiveBounds& b, Objective objective, long ticks_per_second) {
  return BoundValue(b, objective, ticks_per_second).ToJson();
}

}  // namespace ctb
