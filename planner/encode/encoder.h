// The MiniZinc encoding of a state-planning problem (thesis chapter 3, contract sections 2-3).
//
// Time is integer: one tick is the domain's time_resolution. Stage k lies between events e[k]
// and e[k+1]; the decision per automaton a and event k+1 is X[a,k], the transition that fires
// there (0: none). Locations L, entry times N and commands U follow from X. Event g is the one
// at which the end state is accepted; events after g are padding (same time, no transition), so
// a model with horizon H holds every plan with at most H events.
//
// The model text is printed from checked syntax trees and integer codes only; the numeric
// tables go to a JSON data file.
#pragma once

#include <optional>
#include <utility>
#include <string>
#include <vector>

#include "planner/analyze/symmetry.h"
#include "planner/model/domain.h"
#include "planner/model/json_io.h"
#include "planner/model/state_plan.h"
#include "planner/model/trajectory.h"

namespace ctb {

// Facts derived once per (domain, state plan): ticks, the time bound, which commands are read
// outside their own automaton's guards.
struct ProblemInfo {
  long ticks_per_second = 1;            // 1 / time_resolution
  std::vector<long> lo, hi;             // per global transition id 1..NT (index 0 unused), ticks;
                                        // hi = -1 when unbounded
  std::vector<int> owner;               // automaton of each global transition id
  std::vector<std::vector<int>> transitions_of;  // global ids per automaton
  std::vector<bool> command_public;     // command read by another automaton or the state plan
  long max_lo = 0;                      // ticks
  long bound_sum = 0;                   // sum of episode and temporal lower bounds, ticks
  long min_cost = 0;                    // smallest transition cost (0 when there are none)
  long time_offset = 0;                 // replanning: `now` (ticks); the future starts there
  // Interchangeable automata (analyze/symmetry.h): not filled by Analyze(); whoever wants the
  // models to order them sets FindSymmetries(d, sp) here (the horizon solver does).
  std::vector<SymmetryOrbit> symmetries;

  // Latest event time any plan with H events needs (see docs/encoding.md for the argument).
  long TimeBound(int horizon) const {
    return time_offset + bound_sum + static_cast<long>(horizon) * max_lo;
  }
};

ProblemInfo Analyze(const Domain& d, const StatePlan& sp);

struct EncodeOptions {
  int horizon = 10;
  Objective objective = Objective::kCost;
  // Only plans strictly better than this objective value (in the model's units) are wanted.
  std::optional<long> better_than;
  // A lower bound every plan obeys (solve/bounds.h), in the model's units: a redundant constraint
  // that lets branch and bound stop at the first plan that meets it.
  std::optional<long> at_least;
  // Search strategy (see encode_objective.cpp); "default" leaves it to Gecode.
  std::string search = "g_first";
  // The redundant constraints (entry <= event time, minimum time between locations, cost-to-go,
  // cost >= events); off only to measure what they bring (bench/).
  bool redundant = true;
  // Symmetry breaking: the units of each orbit of ProblemInfo::symmetries in lexicographic order
  // of their locations and entry times (encode_symmetry.cpp). Sound because every plan has a
  // symmetric image of equal objective in that order; so never with a model that fixes or hints
  // at part of a plan (a history, a baseline, a warm start), where the image may be excluded:
  // with `history` or `minimize_changes` it is left out whatever this says.
  bool symmetry = true;
  // Relaxed runs: events before g may carry no transition (a part's events that another part
  // makes). Used only to prove lower bounds for the split (docs/encoding.md).
  bool idle_events = false;
  // Replanning (planner/replan): the run's first events are this fixed history (not owned): its
  // events, locations, entry times and transitions are fixed, no model rule applies to them,
  // g >= p and every later event before g is at or after history->now (encode_history.cpp).
  const History* history = nullptr;
  // Replanning with keep "min_change": plans whose objective is at most objective_at_most (model
  // units), minimising the changes against `baseline` (global transition id, time in ticks: the
  // previous plan's transitions at or after now): added + dropped + moved transitions.
  bool minimize_changes = false;
  long objective_at_most = 0;
  std::vector<std::pair<int, long>> baseline;
};

// One model as data rather than text: what Encode() prints, for an engine that builds its own
// model from the checked trees (planner/smt). Pointers are not owned and must outlive the run.
struct ModelSpec {
  const Domain* d = nullptr;
  const StatePlan* sp = nullptr;
  const ProblemInfo* info = nullptr;
  EncodeOptions opts;
};

struct Encoding {
  std::string model;  // MiniZinc text
  Json data;          // the .json data file
  long time_bound = 0;
  // Objective in model units = cost * objective_cost_factor + makespan_ticks * makespan_factor.
  long objective_cost_factor = 1;
  long objective_makespan_factor = 0;
};

Encoding Encode(const Domain& d, const StatePlan& sp, const ProblemInfo& info,
                const EncodeOptions& opts);

// The objective in model units is cost * first + makespan_ticks * second. For
// cost_then_makespan the cost weight depends on the horizon's time bound.
std::pair<long, long> ObjectiveFactors(Objective objective, long time_bound);

}  // namespace ctb
