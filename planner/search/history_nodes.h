// Internal to the search library: where the first-plan engine starts when replanning
// (planner/replan, docs/replanning.md). The history's stages 0..p become the first nodes of the
// run, taken as reported: their times, locations, entry times (the clocks of timed locations) and
// fired transitions are the history's, and no rule of the model is checked on them (a robot may
// have been late, an observation may be a jump no transition explains). The state plan's
// monitors follow them by the engine's own rules (Expander::Reported): episodes started with
// their start, temporal constraints whose first event happened with its time, the maintenance
// constraint on every stage. The search goes on from the last node with every event at or after
// `now` (Expander::SetEarliest), as the exact engines' history encoding has it
// (planner/encode/encode_history.cpp).
#pragma once

#include <vector>

#include "planner/model/domain.h"
#include "planner/model/trajectory.h"
#include "planner/search/expand.h"

namespace ctb::search {

// The nodes of stages 0..p, each the parent of the next (node k at index k, parent k - 1), with
// the history's cost so far. Empty when the run cannot be a plan any more as the engine reads
// it: the state plan broken on a history stage (by the engine's rules, which end episodes and
// accept temporal constraints as early as they may), or the end state accepted before stage p.
std::vector<Node> HistoryNodes(const Expander& ex, const Domain& d, const History& h);

}  // namespace ctb::search
