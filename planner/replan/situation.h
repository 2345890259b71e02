// Internal to planner/replan: the request read into the planner's terms (a fixed History, the
// blocked transitions, the previous plan's future) with every error at its JSON pointer.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "planner/model/domain.h"
#include "planner/model/error.h"
#include "planner/model/state_plan.h"
#include "planner/model/trajectory.h"
#include "planner/replan/replan.h"

namespace ctb::replan {

struct Blocked {
  int automaton = 0;
  std::vector<int> transitions;  // every transition of the automaton from `from` to `to`
  std::string pointer;           // /blocked/k
};

// A transition of the previous plan at or after now (the diff's baseline).
struct Planned {
  int automaton = 0;
  int transition = 0;
  long time = 0;  // ticks
};

struct Situation {
  long tps = 1;
  History history;  // ticks
  std::vector<Blocked> blocked;
  Domain model_domain;     // blocked transitions keep their index, with guard `false`
  Domain analysis_domain;  // blocked transitions removed (for bounds and static checks)
  bool have_previous = false;
  std::vector<Planned> baseline;
  int previous_future_events = 0;  // the previous plan's events at or after now
  long history_cost = 0;
};

// Reads and checks the request against the domain and state plan. keep "started" fills
// history.keep_next from the previous plan.
std::optional<Error> BuildSituation(const Domain& d, const StatePlan& sp, const ReplanRequest& req,
                                    Keep keep, Situation& out);

}  // namespace ctb::replan

namespace ctb::replan {

// The domain with these blocked transitions' guards made `false` (indices kept), and without them.
void BlockedDomains(const Domain& d, const std::vector<Blocked>& blocked, Domain& model,
                    Domain& analysis);

}  // namespace ctb::replan
