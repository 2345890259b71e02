// The makespan bound raised by the zone search with a deadline (bounds.h, RaiseMakespanBound).
// The search over-approximates the runs (zone_reach.h): when no run accepts the end state within
// D ticks, no plan does, so every plan's makespan is at least D + 1. Refutation is monotone in D
// (a run within D is one within every later deadline), so the bound is found by bisection.
#include <algorithm>
#include <chrono>
#include <cstdint>

#include "planner/analyze/bounds.h"
#include "planner/analyze/zone_reach.h"

namespace ctb {

namespace {

constexpr long kMaxWholeTicks = 1000;

}  // namespace

MakespanProof RaiseMakespanBound(const Domain& d, const StatePlan& sp, long bound_ticks,
                                 long plan_ticks, const MakespanProofBudget& budget) {
  using SteadyClock = std::chrono::steady_clock;
  const auto t0 = SteadyClock::now();
  MakespanProof out;
  out.makespan_ticks = bound_ticks;
  if (d.automata.size() > analysis::kMaxZoneAutomata || plan_ticks <= bound_ticks ||
      budget.ms <= 0 || !RemainingTime::Applies(sp))
    return out;
  analysis::ZoneQuestion q = analysis::WholePlan(d, sp, true);
  // A plan's events are at whole ticks: each delay of 0, 1, 2, ... ticks is a successor of its
  // own, which pays while the plan is a few hundred ticks long; beyond, dense zones (a fine time
  // resolution would make millions of them).
  q.whole_ticks = plan_ticks <= kMaxWholeTicks;
  analysis::ZoneBudget b{budget.states, t0 + std::chrono::milliseconds(budget.ms), budget.cancel};
  // No run within `deadline`: proven, every plan ends later.
  auto refuted = [&](std::int64_t deadline) {
    q.deadline = deadline;
    ++out.searches;
    const long before = b.states;
    const bool no_run = analysis::SearchZones(d, sp, q, b) == analysis::Reach::kNoRun;
    out.states += before - std::max(0L, b.states);
    return no_run;
  };
  // The question that ends the search first: nothing within the plan's makespan less a tick.
  std::int64_t bad = bound_ticks - 1, good = plan_ticks - 1;  // bad: refuted (known)
  if (refuted(good))
    bad = good;
  else
    analysis::NarrowRefuted(bad, good, refuted, [&] {
      return b.states > 0 && SteadyClock::now() < b.deadline &&
             !(budget.cancel && budget.cancel->load());
    });
  out.makespan_ticks = std::max(bound_ticks, static_cast<long>(bad) + 1);
  out.ms = std::chrono::duration_cast<std::chrono::milliseconds>(SteadyClock::now() - t0).count();
  return out;
}

}  // namespace ctb
