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

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
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
  // When >= 0: the end state is accepted no later than this many ticks after e[0] (a clock of
  // its own, never reset). No run within it: every plan's makespan is above it.
  std::int64_t deadline = -1;
  // With a deadline: events at whole ticks only, as in every plan (the valuations stay points,
  // but for freed clocks, and the search explores each delay of 0, 1, ... ticks: for deadlines
  // of a few hundred ticks). Exact for plans, not for dense runs.
  bool whole_ticks = false;
};

ZoneQuestion WholePlan(const Domain& d, const StatePlan& sp, bool clocks_known);

enum class Reach { kNoRun, kRun, kUnknown };

// Each event may move any subset of the automata: beyond this many, one state has too many
// successors for a proof within a budget (a team of 8 robots and 3 doors spent it all without
// one), and the searches of this header are not started.
constexpr std::size_t kMaxZoneAutomata = 8;

// Limits shared by the searches of one analysis.
struct ZoneBudget {
  long states = 0;  // symbolic states left to expand
  std::chrono::steady_clock::time_point deadline;
  const std::atomic<bool>* cancel = nullptr;  // set: stop as at the deadline (no proof)
};

Reach SearchZones(const Domain& d, const StatePlan& sp, const ZoneQuestion& q, ZoneBudget& budget);

// Bisection over a bound or deadline whose refutation is monotone (a tighter one keeps fewer
// runs): `bad` is refuted, `good` is not shown to be (either may be the larger); narrows the two
// until they are adjacent or `more` (when given) says stop.
void NarrowRefuted(std::int64_t& bad, std::int64_t& good,
                   const std::function<bool(std::int64_t)>& refuted,
                   const std::function<bool()>& more = nullptr);

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
