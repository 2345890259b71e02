// Internal to planner/analyze: reachability of the end state in the product of the automata and
// the state plan's accepting automata, with the clocks as zones (dbm.h), as UPPAAL checks
// timed automata (docs/explain.md, "Zones"). When no run reaches the end state, whatever its
// number of events, no plan exists: a proof for any horizon.
//
// The search follows the contract's semantics (the verifier, planner/verify/verifier.cpp, is the
// reference for each rule) and over-approximates only what it cannot read: atoms over commands
// and fixed stages other than 0 may take either value, at every event independently. Time is
// dense (every plan in ticks is a dense run). Every plan is a run of the search, so "no run" is
// a proof; a run found may not be a plan (then nothing is claimed).
//
// Thread-safe; no shared state. The searches of one call share a budget (100 ms, 60,000 states;
// about 32 MB of zones per search); beyond, no proof. Domains of more than 8 automata are not
// searched.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "planner/analyze/analyze.h"

namespace ctb::analysis {

// The state plan as one search sees it: the parts it keeps and their bounds in ticks.
struct ZoneQuestion {
  long tps = 1;  // ticks per second
  bool goal = true, maintenance = true;
  std::vector<char> episodes, temporals, events;  // kept, per part
  std::vector<std::int64_t> ep_lo, ep_hi, tc_lo, tc_hi;
  bool clocks_known = true;  // every clock is 0 at e[0]; else any value (a run under way)
};

ZoneQuestion WholePlan(const Domain& d, const StatePlan& sp, bool clocks_known);

enum class Reach { kNoRun, kRun, kUnknown };

// Limits shared by the searches of one analysis.
struct ZoneBudget {
  long states = 0;  // symbolic states left to expand
  std::chrono::steady_clock::time_point deadline;
};

Reach SearchZones(const Domain& d, const StatePlan& sp, const ZoneQuestion& q, ZoneBudget& budget);

struct ZoneConflict {
  std::vector<std::string> parts;  // a minimal set for the search
  std::string text;
  std::vector<BoundHint> hints;  // per bound of the parts: the least value no longer refuted
};

// The conflict the search proves on the whole plan, reduced to a minimal set of parts, with
// hints; nullopt when a run exists or the budget ran out.
std::optional<ZoneConflict> FindZoneConflict(const Domain& d, const StatePlan& sp,
                                             bool clocks_known);

// Per bound of the parts named (pointers; only they are kept): the least value the search no
// longer refutes. Empty when the search does not refute those parts together.
std::vector<BoundHint> FindZoneHints(const Domain& d, const StatePlan& sp,
                                     const std::vector<std::string>& parts, bool clocks_known);

}  // namespace ctb::analysis
