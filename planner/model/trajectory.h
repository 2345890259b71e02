// A plan as a run of the automata: what the extractor builds from a solver answer, what the
// verifier replays, and what is printed as the contract's trajectory JSON (section 5).
#pragma once

#include <memory>
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

// A location change that no transition explains, observed at `now` while replanning (contract
// section 11): `from` may equal `to` (an automaton still where the model says it must have left).
struct ObservedJump {
  int event = 0;
  int automaton = 0;
  int from = 0;
  int to = 0;
};

// The fixed beginning of a run (replanning, planner/replan): stages 0..p and the transitions and
// jumps at events 1..p are as reported, never checked against the model's durations, guards or
// automatic transitions; every later event is at or after `now` and obeys the model.
struct History {
  std::vector<long> times;                 // e[0..p], ticks; times[0] = 0
  std::vector<std::vector<int>> locations;  // [automaton][stage 0..p]
  std::vector<std::vector<long>> entry;     // [automaton][stage 0..p]: entry time, ticks
  std::vector<FiredTransition> fired;       // at events 1..p, in event order
  std::vector<ObservedJump> jumps;          // at events 1..p
  long now = 0;                             // ticks
  // keep: "started" (planner/replan): (automaton, transition) whose next transition must be this.
  std::vector<std::pair<int, int>> keep_next;
  int events() const { return static_cast<int>(times.size()) - 1; }
};

// Everything is indexed by event/stage up to the goal event g (stages 0..g).
struct Trajectory {
  std::vector<long> events;                 // e[0..g], ticks
  std::vector<std::vector<int>> locations;  // [automaton][stage 0..g]
  std::vector<std::vector<int>> commands;   // [automaton][stage 0..g]; 0 = no-op
  std::vector<FiredTransition> fired;       // in event order
  std::vector<std::pair<int, int>> episodes;   // (start event, end event) per episode
  std::vector<std::pair<int, int>> temporals;  // (event1, event2) per temporal constraint
  // (event1, event2) per order (state_plan.h Order); for `every`, event2 is its last firing
  // (event1 when none).
  std::vector<std::pair<int, int>> orders;
  int goal_event = 0;
  int horizon = 0;  // the model's H
  // Set when the run begins with a fixed history (replanning); null otherwise.
  std::shared_ptr<const History> history;
};

// The contract's trajectory JSON without status/objective/stats (added by the caller). With a
// history, its transitions carry "executed": true and its jumps appear as transitions with
// "observed": true.
Json TrajectoryToJson(const Trajectory& t, const Domain& d, const StatePlan& sp,
                      long ticks_per_second);

long TrajectoryCost(const Trajectory& t, const Domain& d);

}  // namespace ctb
