// Internal to planner/replan: the future's transitions against the previous plan's.
#pragma once

#include "planner/model/json_io.h"
#include "planner/replan/situation.h"

namespace ctb::replan {

// {"kept", "moved", "added", "dropped"}: items {"automaton", "from", "to", "command"?,
// "time_before"?, "time_after"?} keyed by (automaton, from, to). The plan's transitions after
// the history are the future. Same key at the same time: kept; the remaining ones of one key
// paired in time order: moved; the rest: added or dropped.
Json DiffAgainstPrevious(const Trajectory& plan, const Domain& d, const Situation& s);

// moved + added + dropped.
long Changes(const Json& diff);

}  // namespace ctb::replan
