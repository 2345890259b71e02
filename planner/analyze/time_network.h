// Internal to planner/analyze: the state plan as a simple temporal network whose edges come from
// the automata's timing (docs/explain.md, "The time network"). A negative cycle is a proof that
// no plan exists, whatever the number of events.
//
// Nodes: the origin e[0] = 0, each episode's start and end, each temporal constraint's first
// (activating) and accepting event. Edges, each a difference constraint x_v - x_u <= w that holds
// on every run of the abstraction (analysis::Abstraction):
//   - the state plan's bounds (episode length, time between a temporal constraint's events) and
//     shared events (equal times);
//   - earliest times: a node's condition needs locations that no run enters earlier (shortest
//     paths over lower durations, a transition no earlier than the locations its guard needs);
//   - the origin: a state condition true in the initial state holds at e[0], so its first
//     occurrence is at time 0;
//   - order and travel: when a node's condition cannot hold at any event before the first
//     occurrence of another's (a condition on one automaton's locations whose every path to the
//     second passes through it), or when an episode's state constraint keeps an automaton in
//     locations where the other condition cannot hold, the later node comes at least the least
//     travel time between their locations after the earlier one.
// Thread-safe; no shared state.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "planner/analyze/abstraction.h"
#include "planner/analyze/analyze.h"

namespace ctb::analysis {

struct TimeConflict {
  std::vector<std::string> parts;  // a minimal set for the network (maintenance last when used)
  std::string text;
  std::vector<BoundHint> hints;    // per bound of the parts: the least value no longer refuted
};

// The smallest conflict the network proves on `ab`; `maintenance` is the pointer of the
// maintenance constraint when `ab` was built under it (added to the parts), else empty.
std::optional<TimeConflict> FindTimeConflict(const Domain& d, const StatePlan& sp,
                                             const Abstraction& ab, const std::string& maintenance);

}  // namespace ctb::analysis
