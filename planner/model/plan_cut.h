// The shape of a cut of the conflict-directed search among plans (state_plan.h PlanCut): which
// event each of its points stands for, read the same way by the MiniZinc encoding
// (encode_state_plan.cpp EmitCuts) and by the check on a trajectory (flexible/cut.h CutMatches).
//
// Points that must share one event form a class. A class's event is pinned by what fixes it in
// any plan: the origin (event 0), a mark of the state plan (an episode's start, a temporal
// constraint's event, ...), the goal's event, or, through `next`, the automaton's transition just
// before or after a pinned class's. A class nothing pins is a loop variable over the events: the
// cut then holds for every choice of it.
#pragma once

#include <vector>

#include "planner/model/state_plan.h"

namespace ctb {

struct CutPin {
  enum class Kind { kLoop, kOrigin, kMark, kGoal, kAfter, kBefore };
  Kind kind = Kind::kLoop;
  int mark = -1;        // kMark: index into the cut's marks
  int from_class = -1;  // kAfter / kBefore: the pinned class it follows or precedes
  int automaton = -1;   // kAfter / kBefore: whose transitions
};

struct CutShape {
  std::vector<int> class_of;   // per point
  std::vector<CutPin> pins;    // per class
  std::vector<int> order;      // classes, each after the class it is pinned from
  std::vector<int> loops;      // the loop classes, in order
};

CutShape ShapeOf(const PlanCut& cut);

// Pairs of the cut's points of one automaton: two transitions, so at two events (one plan firing
// never stands for two points, whose links would then be two where that plan has one).
std::vector<std::pair<int, int>> DistinctPairs(const PlanCut& cut);

}  // namespace ctb
