// Work that only helpers can do (issue 18, lever 5): a lower bound for domains like assembly,
// where a block moves only while an arm holds or places it, arms are few and each pick and place
// takes the arm time and transitions.
//
// A transition t of an automaton b the goal pins away from its start is *supported* by a helper
// k in location v when t's guard needs k in v (a positive location atom of its conjunction), no
// other automaton's transition needs k in v, and b cannot take a second transition that needs k
// in v while k stays there (every way back to such a transition needs k elsewhere). Then each of
// b's supported transitions takes a visit of its own by k to v, and each visit is charged a part
// of k's run that no other visit is charged:
//   - its own stay in v, when the goal pins k elsewhere (so k leaves v before the goal): at
//     least the least lower duration (cost, one event) of a transition out of v;
//   - the stay in the location k came from, when that is not a supporting location itself
//     (otherwise that stay is its own visit's): at least the least lower duration (cost, one
//     event) of a transition into v from outside the supporting locations.
// A location of b whose every transition in and out is supported by one helper glues its
// transitions into one *run* on that helper (a block in arm 1 leaves it only by arm 1's
// placing): b needs at least n_b runs of at least c_b each (shortest paths, guards otherwise
// ignored), and at least T_b in all. A run starts no earlier than its helper can first enter the
// location of its first charge (analyze/earliest.h). So, with K helpers, for every release r:
//   goal >= r + max(ceil(sum of T_b released at r or later / K),
//                   the least load some helper gets when the runs released at r or later are
//                   spread over K helpers: with jK+1 runs, some helper has j+1 of them)
// in time and in events; and the helpers' transitions cost at least sum T_b.
// The argument is in docs/encoding.md. Depends on the model and the expression language only.
#pragma once

#include <vector>

#include "planner/analyze/earliest.h"
#include "planner/model/domain.h"
#include "planner/model/state_plan.h"

namespace ctb {

struct Workload {
  long makespan_ticks = 0;  // no plan accepts its end state earlier
  long events = 0;          // nor at an earlier event
  long helper_cost = 0;     // the helpers' transitions cost at least this in all
  std::vector<bool> helper;  // [automaton]: some supported transition's visit is charged to it
};

// `ticks` and `events` are analyze/earliest.h's arrivals in each measure (nullptr: releases at 0).
// A goal that reads a change (both stages) gets no bound (all zero).
Workload ComputeWorkload(const Domain& d, const StatePlan& sp, const EarliestTimes* ticks,
                         const EarliestTimes* events);

}  // namespace ctb
