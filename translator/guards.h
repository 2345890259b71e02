// Meaning guards (docs/translator.md): checks of a state plan that parses and passes the checker
// but may not mean what the user said. Their findings go into the repair loop like the
// checker's; see pipeline.cpp for which of them block a plan when the repairs run out.
#pragma once

#include <string>
#include <vector>

#include "planner/model/domain.h"
#include "planner/model/error.h"
#include "planner/model/json_io.h"
#include "planner/model/state_plan.h"

namespace ctb {

// Durations the command states ("1800 seconds", "30 min", "2 h", "90s"), as written, in order.
std::vector<std::string> StatedDurations(const std::string& command);

// Episodes of the raw answer without a state_constraint (the loader reads it as "true": the
// state need not hold during the episode); one warning each, at the missing key's pointer.
std::vector<Diagnostic> DefaultedStateConstraints(const Json& plan);

// True when the goal holds on the initial stage (commands idle, accepting automata waiting) and
// the plan has no episode or temporal constraint: the plan is empty, reached at time 0.
bool GoalHoldsAtStart(const StatePlan& sp, const Domain& d);

struct MeaningFindings {
  std::vector<Diagnostic> blocking;  // a plan with another meaning: not accepted
  std::vector<Diagnostic> doubtful;  // asked about in a repair; reported if it stays
};

// The guards on a checked plan for a command.
MeaningFindings CheckMeaning(const Json& plan, const StatePlan& sp, const Domain& d,
                             const std::string& command);

// What `after` (a repair) dropped that `before` (the answer it repairs) had: constraints of each
// group and conjuncts of the goal (unless the repair was asked to change the goal:
// goal_flagged). Empty when nothing was dropped or either is not a plan.
std::vector<Diagnostic> Dropped(const Json& before, const Json& after, bool goal_flagged = false);

}  // namespace ctb
