// Static analysis of a checked state plan against its domain: proofs of infeasibility found
// without search, each naming the state-plan parts responsible (contract section 9).
//
// Every check reasons on an over-approximation of the runs of the automata, so a conflict it
// reports is a proof: no plan exists, whatever the horizon. It may miss conflicts (then the
// solver decides). The abstraction:
//   - reachable locations: a fixpoint from the initial state in which a transition can fire when
//     its guard can be true for some combination of locations the other automata can reach
//     (commands and accepting-automaton states may take any value);
//   - at one event, each automaton either stays in a reachable location or takes one of its
//     usable transitions, independently of the others;
//   - the least time between entering two locations: shortest paths over the usable
//     transitions' lower durations.
// A maintenance constraint restricts every stage before the goal event to its locations.
//
// Depends on the model and the expression language only. Thread-safe: no shared state.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "planner/model/domain.h"
#include "planner/model/state_plan.h"

namespace ctb {

// A bound that the check which found a conflict no longer refutes: setting `pointer` (a
// lower_bound or upper_bound) to `value` is the least change that could make the part possible.
struct BoundHint {
  std::string pointer;
  double value = 0;
};

struct StaticConflict {
  // "never_holds": a condition no reachable state satisfies (a change no transition allows, a
  //   location not reachable from the initial state, an episode whose state constraint
  //   contradicts its accepting constraint), possibly because of the maintenance constraint;
  // "deadline": a temporal constraint's upper bound below the least time its two events can be
  //   apart; "shared_event": endpoints that must fall on one event but cannot; "time_network":
  //   the state plan's events as a temporal network (time_network.h); "zones": no run of the
  //   automata and the state plan's accepting automata reaches the end state (zone_reach.h).
  std::string kind;
  std::vector<std::string> parts;  // JSON pointers of state-plan parts, a minimal set
  std::string text;                // one plain sentence
  std::optional<BoundHint> hint;
  // Every bound of the parts with the least value the check no longer refutes (hint among them).
  std::vector<BoundHint> hints;
  // "any_horizon": every check here holds whatever the number of events.
};

// Which checks run (all by default; tests turn routes off to check each alone).
struct AnalysisOptions {
  // Every automaton entered its initial location at e[0] (a new plan); false for a run under
  // way (replanning), whose clocks the state plan does not give.
  bool clocks_at_zero = true;
  bool time_network = true;  // time_network.h
  bool zones = true;         // zone_reach.h, when the other checks find nothing
};

// Every conflict the checks find, smallest sets first (parts of one conflict are not repeated
// as a larger one). Empty when none is found. Runs in milliseconds on the shipped domains; the
// zone search stops after 100 ms.
std::vector<StaticConflict> FindStaticConflicts(const Domain& d, const StatePlan& sp,
                                                const AnalysisOptions& o = {});

// The first of FindStaticConflicts, or nullopt.
std::optional<StaticConflict> FindStaticConflict(const Domain& d, const StatePlan& sp,
                                                 const AnalysisOptions& o = {});

// The least time (seconds) between entering location `from` and entering location `to` of
// automaton a over transitions usable from the initial state; nullopt when `to` cannot follow
// `from`. Exposed for lower bounds elsewhere (e.g. makespan).
std::optional<double> ShortestTime(const Domain& d, const StatePlan& sp, int a, int from, int to);

}  // namespace ctb
