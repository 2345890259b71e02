// Earliest times: a lower bound on when each location can first be entered and on when the end
// state can be accepted, valid for every plan whatever its number of events (issue 9's makespan
// bound). It reasons on the timed behaviour the graph bound of analyze/bounds.h ignores:
//   - guards: a transition fires no earlier than every location its guard needs (a positive
//     location atom of a conjunction; the earliest alternative of a disjunction) is entered, so a
//     robot waits for the door another robot opens;
//   - dwell: an episode whose accepting constraint is exactly "a at l" and whose state constraint
//     needs "a at l" keeps a in l from its first entry for at least the episode's lower bound, so
//     nothing leaves l earlier (the projector stays on for 30 minutes before it can cool down);
//   - the state plan as a simple temporal network: episode starts and ends, temporal constraint
//     events (a constraint whose second event needs it active opens at its first event), shared
//     events and the goal event, with their lower bounds;
//   - return: an automaton an episode holds in l' until the episode ends must then still travel
//     from l' to the location the goal pins it to.
// The argument (each rule holds on every run, by induction over the run's events) is in
// docs/encoding.md. Depends on the model and the expression language only; thread-safe.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "planner/model/domain.h"
#include "planner/model/state_plan.h"

namespace ctb {

// What the bound counts: time in ticks, or events (each transition at an event after the one at
// which its source location and the locations its guard needs were entered; an episode ends at a
// later event than it starts; a temporal constraint with a positive lower bound is accepted at a
// later event than it opens). Dwell is a matter of time only.
enum class Measure { kTicks, kEvents };

struct EarliestTimes {
  static constexpr long kNever = 1L << 60;  // never entered / never holds
  std::vector<std::vector<long>> arrival;   // [automaton][location], ticks or events
  long goal = 0;                            // no plan accepts its end state earlier
};

// The positive location atoms (automaton, location) of e's top-level conjunction that do not use
// a fixed stage: the locations a condition needs.
void RequiredLocations(const Expr& e, std::vector<std::pair<int, int>>& out);

// The least total weight of a path from `from` to every location of the automaton (guards
// ignored); EarliestTimes::kNever where there is none. Weights must be non-negative.
std::vector<long> ShortestFrom(const Automaton& a, int from,
                               const std::function<long(const Transition&)>& weight);

// The earliest goal of the rest of a run from a state under way, for a state plan of a goal and
// a maintenance constraint only (Applies): the arrivals, the goal and the helpers' return of
// ComputeEarliestTimes, with time 0 now, each automaton a in loc[a] since since[a] ticks (no
// less: a larger value is a weaker, still valid, bound) and no transition before now. Each rule
// holds on every continuation of a run through that state, as on every run from e[0].
class RemainingTime {
 public:
  RemainingTime(const Domain& d, const StatePlan& sp);
  ~RemainingTime();
  static bool Applies(const StatePlan& sp);
  long Goal(const std::vector<int>& loc, const std::vector<long>& since) const;

 private:
  struct Tables;  // shortest lower durations between locations; guards as lists of atoms
  const Domain& d_;
  const StatePlan& sp_;
  std::unique_ptr<Tables> tables_;
};

// nullopt when the fixpoint does not settle within its round limit (then no bound is claimed).
std::optional<EarliestTimes> ComputeEarliestTimes(const Domain& d, const StatePlan& sp,
                                                  Measure measure = Measure::kTicks);

}  // namespace ctb
