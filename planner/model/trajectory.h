// A plan as a run of the automata: what the extractor builds from a solver answer, what the
// verifier replays, and what is printed as the contract's trajectory JSON (section 5).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "planner/model/domain.h"
#include "planner/model/error.h"
#include "planner/model/json_io.h"
#include "planner/model/state_plan.h"

namespace ctb {

struct FiredTransition {
  int event = 0;       // k: fires at e[k], between stage k-1 and stage k
  int automaton = 0;
  int transition = 0;  // index within the automaton's transitions
};

// Everything is indexed by event/stage up to the goal event g (stages 0..g).
struct Trajectory {
  std::vector<long> events;                 // e[0..g], ticks
  std::vector<std::vector<int>> locations;  // [automaton][stage 0..g]
  std::vector<std::vector<int>> commands;   // [automaton][stage 0..g]; 0 = no-op
  std::vector<FiredTransition> fired;       // in event order
  std::vector<std::pair<int, int>> episodes;   // (start event, end event) per episode
  std::vector<std::pair<int, int>> temporals;  // (event1, event2) per temporal constraint
  int goal_event = 0;
  int horizon = 0;  // the model's H
};

// The contract's trajectory JSON without status/objective/stats (added by the caller).
Json TrajectoryToJson(const Trajectory& t, const Domain& d, const StatePlan& sp,
                      long ticks_per_second);

long TrajectoryCost(const Trajectory& t, const Domain& d);

}  // namespace ctb
