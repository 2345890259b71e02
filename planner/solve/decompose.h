// Factoring a problem into independent sub-problems (tBurton's idea, the thesis' reference 4):
// automata linked by no guard and no state-plan constraint are solved apart and their plans
// merged. The merged plan is checked by the verifier against the whole problem; callers fall
// back to one model when it fails or when the pieces do not split.
#pragma once

#include <vector>

#include "planner/model/domain.h"
#include "planner/model/state_plan.h"
#include "planner/model/trajectory.h"

namespace ctb {

struct SubProblem {
  std::vector<int> automata;      // global automaton index of each sub-domain automaton
  Domain domain;
  StatePlan plan;
  std::vector<int> episode_map;   // sub episode index -> global index
  std::vector<int> temporal_map;  // sub temporal index -> global index
};

// Splits d/sp into independent parts. Returns fewer than two parts (meaning: do not split)
// when everything is linked, the maintenance constraint is not "true", the goal is a change
// condition, or the goal links the parts otherwise than by a top-level conjunction.
std::vector<SubProblem> SplitProblem(const Domain& d, const StatePlan& sp);

// Merges the parts' plans: events are ordered by time, and the j-th event at a time point of
// every part share one merged event (each part keeps its own order). Episode and temporal
// event indices are mapped to merged events.
Trajectory MergeTrajectories(const std::vector<SubProblem>& parts,
                             const std::vector<Trajectory>& plans, const Domain& d,
                             const StatePlan& sp);

}  // namespace ctb
