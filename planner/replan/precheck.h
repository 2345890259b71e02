// Internal to planner/replan: what the history alone decides, before any solve. The state plan's
// conditions are evaluated on the history's stages (conditions that read commands, an accepting
// automaton's state or a fixed stage are not evaluated: nothing is claimed about them).
#pragma once

#include <optional>
#include <vector>

#include "planner/model/json_io.h"
#include "planner/replan/situation.h"
#include "planner/solve/solve_result.h"
#include "planner/analyze/bounds.h"

namespace ctb::replan {

// Conflicts (section 9's shape plus "broken_at", seconds) for every episode, temporal constraint
// or maintenance constraint the history has already broken; empty when none is certain.
std::vector<ExplanationConflict> BrokenByHistory(const StatePlan& sp, const Situation& s);

// When the goal can no longer be reached from the state at now (a static proof over the domain
// without the blocked transitions): the conflict naming the goal and a minimal set of the
// /blocked/k entries that cut it off (none when the goal is unreachable even without them).
std::optional<ExplanationConflict> GoalCutOff(const Domain& d, const StatePlan& sp,
                                              const Situation& s);

// Lower bounds on the whole run's objective valid for every future given the history: the
// history's cost plus the remaining problem's bounds from the state at now (time-shifted to the
// earliest entry time at now), see docs/replanning.md.
ObjectiveBounds HistoryBounds(const StatePlan& sp, const Situation& s);

}  // namespace ctb::replan
