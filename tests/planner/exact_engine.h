// The truth the bound tests compare with: the exact engine alone (Gecode, g_first), without the
// first-plan engine and told no bound to stop at or constrain, over every plan of at most
// `max_horizon` events.
#pragma once

#include "planner/solve/solve.h"

namespace ctb::testing {

inline SolveOptions ExactEngineAlone(Objective objective, int max_horizon = 10) {
  SolveOptions o;
  o.objective = objective;
  o.max_horizon = max_horizon;
  o.time_limit_ms = 120000;
  o.search = "g_first";
  o.first_plan_ms = 0;
  o.bounds = ObjectiveBounds{};
  return o;
}

}  // namespace ctb::testing
