#include "planner/solve/bounds.h"

#include "planner/analyze/earliest.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <utility>
#include <vector>

namespace ctb {

namespace {

constexpr long kUnreachable = std::numeric_limits<long>::max() / 4;

// Cheapest way, by cost or by the transitions' lower durations (ticks), from `from` to every
// location of the automaton; kUnreachable where there is none.
std::vector<long> Shortest(const Automaton& a, int from, bool by_time, long tps) {
  std::vector<long> dist(a.locations.size(), kUnreachable);
  using Item = std::pair<long, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> q;
  dist[from] = 0;
  q.push({0, from});
  while (!q.empty()) {
    auto [d, l] = q.top();
    q.pop();
    if (d > dist[l]) continue;
    for (const auto& t : a.transitions) {
      if (t.from != l) continue;
      long w = by_time ? std::lround(t.duration.lo * static_cast<double>(tps)) : t.cost;
      if (d + w < dist[t.to]) {
        dist[t.to] = d + w;
        q.push({dist[t.to], t.to});
      }
    }
  }
  return dist;
}

// The least cost (or time) for automaton a to go from its initial location through v (if any)
// to its final location (if any).
long Through(const Automaton& au, int init, int via, int final_loc, bool by_time, long tps) {
  const auto from_init = Shortest(au, init, by_time, tps);
  long first = via >= 0 ? from_init[via] : 0;
  if (first >= kUnreachable) return 0;  // unreachable: infeasibility is not this bound's business
  if (final_loc < 0) return first;
  long second = via >= 0 ? Shortest(au, via, by_time, tps)[final_loc] : from_init[final_loc];
  return second >= kUnreachable ? first : first + second;
}

}  // namespace

void RequiredLocations(const Expr& e, std::vector<std::pair<int, int>>& out) {
  if (e.op == Expr::Op::kAnd) {
    RequiredLocations(e.kids[0], out);
    RequiredLocations(e.kids[1], out);
  } else if (e.op == Expr::Op::kAtom && e.var_kind == VarKind::kLocation && !e.not_equal &&
             e.index.kind != IndexKind::kFixed) {
    out.emplace_back(e.target, e.value_code);
  }
}

bool MeetsLowerBounds(const ObjectiveBounds& b, Objective objective, long cost, long makespan_ticks) {
  switch (objective) {
    case Objective::kCost: return cost <= b.cost;
    case Objective::kMakespan: return makespan_ticks <= b.makespan_ticks;
    case Objective::kCostThenMakespan: return cost <= b.cost && makespan_ticks <= b.makespan_ticks;
  }
  return false;
}

ObjectiveBounds LowerBounds(const Domain& d, const StatePlan& sp) {
  const long tps = std::max(1L, std::lround(1.0 / d.time_resolution));
  const std::size_t na = d.automata.size();
  std::vector<int> final_loc(na, -1);
  std::vector<std::pair<int, int>> goal;
  if (!sp.goal.info.IsChange()) RequiredLocations(sp.goal.expr, goal);
  for (auto [a, loc] : goal) final_loc[a] = loc;
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
  for (std::size_t a = 0; a < na; ++a) {
    const Automaton& au = d.automata[a];
    const int init = sp.initial[a];
    long cost = Through(au, init, -1, final_loc[a], false, tps);
    long time = Through(au, init, -1, final_loc[a], true, tps);
    for (int v : visits[a]) {
      cost = std::max(cost, Through(au, init, v, final_loc[a], false, tps));
      time = std::max(time, Through(au, init, v, final_loc[a], true, tps));
    }
    b.cost += cost;
    b.makespan_ticks = std::max(b.makespan_ticks, time);
  }
  for (const auto& e : sp.episodes) {
    long lower = std::lround(e.lower * static_cast<double>(tps));
    // A state condition on one location starts the episode no earlier than that location can
    // first be entered.
    long start = 0;
    std::vector<std::pair<int, int>> v;
    if (!e.accepting.info.IsChange()) RequiredLocations(e.accepting.expr, v);
    for (auto [a, loc] : v) {
      long t = Shortest(d.automata[a], sp.initial[a], true, tps)[loc];
      if (t < kUnreachable) start = std::max(start, t);
    }
    b.makespan_ticks = std::max(b.makespan_ticks, start + lower);
  }
  for (const auto& t : sp.temporals)
    b.makespan_ticks = std::max(b.makespan_ticks, std::lround(t.lower * static_cast<double>(tps)));
  // Guards, dwell in an episode's location and the state plan's temporal network.
  if (auto earliest = ComputeEarliestTimes(d, sp); earliest && earliest->goal < EarliestTimes::kNever)
    b.makespan_ticks = std::max(b.makespan_ticks, earliest->goal);
  return b;
}

}  // namespace ctb
