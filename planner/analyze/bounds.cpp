#include "planner/analyze/bounds.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>
#include <set>
#include <utility>
#include <vector>

#include "planner/analyze/assignment.h"
#include "planner/analyze/assignment_cost.h"
#include "planner/analyze/clauses.h"
#include "planner/analyze/relaxed_cost.h"
#include "planner/analyze/turns.h"
#include "planner/analyze/workload.h"

namespace ctb {

namespace {

constexpr long kUnreachable = EarliestTimes::kNever;

using Weight = std::function<long(const Transition&)>;

// The least weight for automaton a to go from its initial location through v (if any) to its
// final location (if any).
long Through(const Automaton& au, int init, int via, int final_loc, const Weight& w) {
  const auto from_init = ShortestFrom(au, init, w);
  long first = via >= 0 ? from_init[via] : 0;
  if (first >= kUnreachable) return 0;  // unreachable: infeasibility is not this bound's business
  if (final_loc < 0) return first;
  long second = via >= 0 ? ShortestFrom(au, via, w)[final_loc] : from_init[final_loc];
  return second >= kUnreachable ? first : first + second;
}

// The most automaton a needs: to its final location, through each location it must visit.
long Needs(const Automaton& au, int init, const std::vector<int>& visits, int final_loc,
           const Weight& w) {
  long need = Through(au, init, -1, final_loc, w);
  for (int v : visits) need = std::max(need, Through(au, init, v, final_loc, w));
  return need;
}

// True when `to` can be reached from `from` in the automaton's graph without the transitions
// that need automaton b in location n.
bool ReachableWithout(const Automaton& au, int from, int to, int b, int n) {
  std::vector<bool> seen(au.locations.size(), false);
  std::vector<int> stack{from};
  seen[from] = true;
  while (!stack.empty()) {
    int l = stack.back();
    stack.pop_back();
    if (l == to) return true;
    for (const Transition& t : au.transitions) {
      if (t.from != l || seen[t.to]) continue;
      std::vector<std::pair<int, int>> needs;
      RequiredLocations(t.guard, needs);
      if (std::find(needs.begin(), needs.end(), std::make_pair(b, n)) != needs.end()) continue;
      seen[t.to] = true;
      stack.push_back(t.to);
    }
  }
  return false;
}

// Landmarks: when automaton a must enter m and cannot get there from its initial location
// without a transition whose guard needs b in n, b must visit n too (then its own cheapest way
// passes through n). Adds these visits, to a fixpoint.
void AddGuardLandmarks(const Domain& d, const StatePlan& sp, const std::vector<int>& final_loc,
                       std::vector<std::vector<int>>& visits) {
  std::set<std::pair<int, int>> known;
  std::deque<std::pair<int, int>> work;
  auto add = [&](int a, int l, bool visit) {
    if (!known.insert({a, l}).second) return;
    work.emplace_back(a, l);
    if (visit) visits[a].push_back(l);
  };
  for (std::size_t a = 0; a < visits.size(); ++a) {
    if (final_loc[a] >= 0) add(static_cast<int>(a), final_loc[a], false);
    for (int v : std::vector<int>(visits[a])) add(static_cast<int>(a), v, false);
  }
  while (!work.empty()) {
    auto [a, m] = work.front();
    work.pop_front();
    const Automaton& au = d.automata[a];
    if (m == sp.initial[a]) continue;
    std::vector<std::pair<int, int>> needs;
    for (const Transition& t : au.transitions) RequiredLocations(t.guard, needs);
    for (auto [b, n] : needs)
      if (!known.count({b, n}) && !ReachableWithout(au, sp.initial[a], m, b, n)) add(b, n, true);
  }
}

}  // namespace

bool MeetsLowerBounds(const ObjectiveBounds& b, Objective objective, long cost, long makespan_ticks) {
  switch (objective) {
    case Objective::kCost: return cost <= b.cost;
    case Objective::kMakespan: return makespan_ticks <= b.makespan_ticks;
    case Objective::kCostThenMakespan: return cost <= b.cost && makespan_ticks <= b.makespan_ticks;
  }
  return false;
}

ObjectiveValue BoundValue(const ObjectiveBounds& b, Objective objective, long ticks_per_second) {
  return {objective, b.cost, b.makespan_ticks, ticks_per_second};
}

namespace {

// How many times the least-cost rule cuts the model (each cut computes the bounds again).
constexpr int kMaxLeastCostCuts = 3;

// The makespan bound of plans that cost at most `budget`: the cheap enough assignment that ends
// soonest, and the bounds of the same model in which the transitions into locations no such plan
// enters lead nowhere (their automaton stays where it is: a self-loop keeps every index and adds
// no way anywhere). Every plan of that cost is a plan of that model, since it never takes those
// transitions.
long LeastCostMakespan(const Domain& d, const StatePlan& sp, const BoundOptions& o,
                       const std::vector<std::vector<int>>& visits,
                       const std::vector<long>& own_cost, const std::vector<int>& final_loc,
                       const EarliestTimes* earliest, long budget) {
  const WithinBudget reach = ReachWithinBudget(d, sp, visits, own_cost, final_loc,
                                               earliest ? &earliest->arrival : nullptr, budget);
  if (reach.costly.empty()) return reach.bottleneck;
  Domain cut = d;
  for (auto [a, l] : reach.costly)
    for (Transition& t : cut.automata[a].transitions)
      if (t.to == l) t.to = t.from;
  // The cut model's bounds, with the rule again on it (its arrival times, its own dear locations)
  // at the same budget: a plan of that cost never enters a cut location, so it is a plan of the
  // cut model.
  BoundOptions inner = o;
  inner.assignment_cost = false;  // only the makespan is read
  inner.least_cost_makespan = o.least_cost_cuts + 1 < kMaxLeastCostCuts;
  inner.least_cost_budget = budget;
  inner.least_cost_cuts = o.least_cost_cuts + 1;
  return std::max(reach.bottleneck, LowerBounds(cut, sp, inner).makespan_ticks);
}

}  // namespace

ObjectiveBounds LowerBounds(const Domain& d, const StatePlan& sp, const BoundOptions& o) {
  const long tps = std::max(1L, std::lround(1.0 / d.time_resolution));
  const Weight by_cost = [](const Transition& t) { return t.cost; };
  const Weight by_time = [tps](const Transition& t) {
    return std::lround(t.duration.lo * static_cast<double>(tps));
  };
  const Weight by_event = [](const Transition&) { return 1L; };
  const std::size_t na = d.automata.size();
  // The goal's locations; for the event count at either stage of a change goal too (each is
  // reached by the goal event).
  std::vector<int> final_loc(na, -1), last_loc(na, -1);
  std::vector<std::pair<int, int>> goal;
  RequiredLocations(sp.goal.expr, goal);
  for (auto [a, loc] : goal) last_loc[a] = loc;
  if (!sp.goal.info.IsChange()) final_loc = last_loc;
  std::vector<std::vector<int>> visits(na);
  auto add_visits = [&](const Condition& c) {
    std::vector<std::pair<int, int>> v;
    RequiredLocations(c.expr, v);
    for (auto [a, loc] : v) visits[a].push_back(loc);
  };
  for (const auto& e : sp.episodes) add_visits(e.accepting);
  for (const auto& t : sp.temporals) {
    add_visits(t.event1);
    add_visits(t.event2);
  }
  ObjectiveBounds b;
  // Each transition of an automaton at an event of its own.
  for (std::size_t a = 0; a < na; ++a)
    b.events = std::max(b.events, Needs(d.automata[a], sp.initial[a], visits[a], last_loc[a], by_event));
  AddGuardLandmarks(d, sp, final_loc, visits);
  std::vector<long> own_cost(na, 0);
  for (std::size_t a = 0; a < na; ++a) {
    own_cost[a] = Needs(d.automata[a], sp.initial[a], visits[a], final_loc[a], by_cost);
    b.cost += own_cost[a];
    b.makespan_ticks = std::max(b.makespan_ticks,
                                Needs(d.automata[a], sp.initial[a], visits[a], final_loc[a], by_time));
  }
  for (const auto& e : sp.episodes) {
    long lower = std::lround(e.lower * static_cast<double>(tps));
    // A state condition on one location starts the episode no earlier than that location can
    // first be entered.
    long start = 0;
    std::vector<std::pair<int, int>> v;
    if (!e.accepting.info.IsChange()) RequiredLocations(e.accepting.expr, v);
    for (auto [a, loc] : v) {
      long t = ShortestFrom(d.automata[a], sp.initial[a], by_time)[loc];
      if (t < kUnreachable) start = std::max(start, t);
    }
    b.makespan_ticks = std::max(b.makespan_ticks, start + lower);
  }
  for (const auto& t : sp.temporals)
    b.makespan_ticks = std::max(b.makespan_ticks, std::lround(t.lower * static_cast<double>(tps)));
  // The delete relaxation counts the help automata give each other (analyze/relaxed_cost.h).
  if (auto relaxed = RelaxedCostBound(d, sp)) b.cost = std::max(b.cost, *relaxed);
  // A goal whose clauses several automata may serve, each automaton at its own cost
  // (analyze/assignment_cost.h).
  if (o.assignment_cost) b.cost = std::max(b.cost, AssignmentCostBound(d, sp, visits, own_cost, b.cost));
  // Guards, dwell in an episode's location and the state plan's temporal network.
  const auto earliest = ComputeEarliestTimes(d, sp);
  if (earliest && earliest->goal < EarliestTimes::kNever)
    b.makespan_ticks = std::max(b.makespan_ticks, earliest->goal);
  // The same rules, counted in events.
  const auto ev = ComputeEarliestTimes(d, sp, Measure::kEvents);
  if (ev && ev->goal < EarliestTimes::kNever) b.events = std::max(b.events, ev->goal);
  // A goal that several automata may serve, each in one location (analyze/assignment.h).
  if (!sp.goal.info.IsChange()) {
    const Clauses goal_clauses = ToClauses(sp.goal.expr);
    if (earliest)
      b.makespan_ticks = std::max(
          b.makespan_ticks, AssignmentBound(goal_clauses, earliest->arrival, kUnreachable));
    if (ev) b.events = std::max(b.events, AssignmentBound(goal_clauses, ev->arrival, kUnreachable));
  }
  // Work only helpers can do, spread over the helpers (analyze/workload.h). The helpers' own
  // ways and the work charged to them count the same transitions: the larger of the two.
  const Workload w = ComputeWorkload(d, sp, earliest ? &*earliest : nullptr, ev ? &*ev : nullptr);
  b.makespan_ticks = std::max(b.makespan_ticks, w.makespan_ticks);
  // Locations the maintenance constraint lets only one automaton occupy at a time.
  if (o.turns)
    b.makespan_ticks = std::max(
        b.makespan_ticks, ComputeTurnBound(d, sp, earliest ? &*earliest : nullptr).makespan_ticks);
  b.events = std::max(b.events, w.events);
  long others = 0, helpers = 0;
  for (std::size_t a = 0; a < na; ++a) (w.helper[a] ? helpers : others) += own_cost[a];
  b.cost = std::max(b.cost, others + std::max(helpers, w.helper_cost));
  if (o.least_cost_makespan)
    b.makespan_ticks = std::max(
        b.makespan_ticks,
        LeastCostMakespan(d, sp, o, visits, own_cost, final_loc, earliest ? &*earliest : nullptr,
                          std::max(b.cost, o.least_cost_budget)));
  return b;
}

}  // namespace ctb
