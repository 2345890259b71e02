// Conflict-directed search among plans (contract section 13, docs/uncertainty.md): from a plan
// whose network is not dynamically controllable and the conflict the checker found, a cut
// (state_plan.h PlanCut) that every plan whose network holds the same conflict contains. Adding the
// cut to the state plan removes only plans that are not controllable, so the planner's next best
// plan is the best of those that may be.
//
// Why it is sound: the conflict's links, restated of another plan (the same transitions, each
// following the same one of its automaton; the same marks of the state plan; the same event order
// where an observer kept it), are links of that plan's network too, or implied by its links
// (docs/uncertainty.md). A network that holds a sub-network that is not dynamically controllable
// is not either. The one tick by which an order keeps an automatic transition after another is
// not restated (another plan may have the two at one time): the conflict is checked again
// without it, and no cut is made when it no longer stands.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "planner/flexible/flexible.h"

namespace ctb::flexible {

// nullopt, with `why_not`, when a link of the conflict is one the cut cannot restate (an automatic
// transition's cause, an overstay, a pinned time), the plan's order is rigid because of where its
// own marks fall, the conflict does not stand without the ticks above, or it would need more than
// two free events.
std::optional<PlanCut> CutFromConflict(const FlexiblePlan& f, const Trajectory& plan,
                                       const std::vector<int>& conflict, std::string* why_not);

// Whether trajectory `t` (of state plan `sp`) contains the cut's pattern, read as the MiniZinc
// encoding reads it (plan_cut.h).
bool CutMatches(const PlanCut& cut, const Trajectory& t, const StatePlan& sp);

}  // namespace ctb::flexible
