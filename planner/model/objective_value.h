// An objective's value as the contract writes it (section 5): a cost is a count of transition
// costs, a makespan is seconds; the kind says which one is "the" value, cost_then_makespan being
// both. Plans' values and bounds travel as this, typed, until a front end writes them.
#pragma once

#include "planner/model/json_io.h"
#include "planner/model/state_plan.h"

namespace ctb {

struct ObjectiveValue {
  Objective kind = Objective::kCost;
  long cost = 0;
  long makespan_ticks = 0;
  long ticks_per_second = 1;

  double MakespanSeconds() const {
    return static_cast<double>(makespan_ticks) / static_cast<double>(ticks_per_second);
  }
  // Seconds: a whole number on a 1 s grid (2430), else a double (12.5; 12.0 on a finer grid).
  Json MakespanJson() const {
    return ticks_per_second == 1 ? Json(makespan_ticks) : Json(MakespanSeconds());
  }
  // The kind's shape: the cost, the makespan, or {"cost", "makespan"}.
  Json ToJson() const {
    switch (kind) {
      case Objective::kCost: return cost;
      case Objective::kMakespan: return MakespanJson();
      case Objective::kCostThenMakespan: return {{"cost", cost}, {"makespan", MakespanJson()}};
    }
    return nullptr;
  }
};

}  // namespace ctb
