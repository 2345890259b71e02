#include "planner/search/neighbourhood.h"

#include <algorithm>
#include <chrono>

#include "planner/search/first_plan.h"

namespace ctb {

namespace {

using Clock = std::chrono::steady_clock;
using Value = std::pair<long, long>;

// Pairs are tried among the automata whose last transition comes latest: at most this many.
constexpr std::size_t kPairPool = 12;
// A round's share of the budget: at least this, else the budget over this many rounds.
constexpr long kMinRoundMs = 10;
constexpr long kRoundShare = 24;

Value ValueOf(Objective objective, long cost, long makespan) {
  switch (objective) {
    case Objective::kCost: return {cost, 0};
    case Objective::kMakespan: return {makespan, 0};
    case Objective::kCostThenMakespan: return {cost, makespan};
  }
  return {0, 0};
}

// The automata by the event of their last transition, latest first (those that end the plan);
// automata that never move come last, in index order.
std::vector<int> ByLastMove(const Trajectory& plan, std::size_t automata) {
  std::vector<int> last(automata, -1);
  for (const auto& f : plan.fired) last[f.automaton] = std::max(last[f.automaton], f.event);
  std::vector<int> order(automata);
  for (std::size_t a = 0; a < automata; ++a) order[a] = static_cast<int>(a);
  std::stable_sort(order.begin(), order.end(), [&](int x, int y) { return last[x] > last[y]; });
  return order;
}

// A round: the scripts it holds automata to (nullopt: free).
using Scripts = std::vector<std::optional<std::vector<int>>>;

// The same transition in automaton b as transition ti of automaton a (same locations and
// command, by name); -1 when b has none.
int SameIn(const Domain& d, int a, int ti, int b) {
  const Automaton& A = d.automata[a];
  const Automaton& B = d.automata[b];
  const Transition& t = A.transitions[ti];
  auto command = [](const Automaton& au, const Transition& tr) {
    return tr.commanded && tr.command > 0 ? au.commands[tr.command - 1] : std::string();
  };
  for (std::size_t k = 0; k < B.transitions.size(); ++k) {
    const Transition& u = B.transitions[k];
    if (u.commanded == t.commanded && B.locations[u.from] == A.locations[t.from] &&
        B.locations[u.to] == A.locations[t.to] && command(B, u) == command(A, t))
      return static_cast<int>(k);
  }
  return -1;
}

// Automaton a's transitions from..to of `script`, written as automaton b's; nullopt when b lacks one.
std::optional<std::vector<int>> Mapped(const Domain& d, int a, const std::vector<int>& script,
                                       std::size_t from, std::size_t to, int b) {
  std::vector<int> out;
  for (std::size_t i = from; i < to; ++i) {
    const int k = a == b ? script[i] : SameIn(d, a, script[i], b);
    if (k < 0) return std::nullopt;
    out.push_back(k);
  }
  return out;
}

// The rounds that re-time a plan whose automata a and b trade the starts of their routes at a
// location both pass through (one opens the door the other waited at; with both starts, their
// whole routes): every automaton held to its script.
void Splices(const Domain& d, const Trajectory& plan, const std::vector<std::vector<int>>& taken,
             int a, int b, std::vector<Scripts>& out) {
  if (d.automata[a].locations[plan.locations[a][0]] != d.automata[b].locations[plan.locations[b][0]])
    return;
  // The location before each step of a script, and the last.
  auto visits = [&](int x) {
    std::vector<std::string> v = {d.automata[x].locations[plan.locations[x][0]]};
    for (int ti : taken[x]) v.push_back(d.automata[x].locations[d.automata[x].transitions[ti].to]);
    return v;
  };
  const std::vector<std::string> va = visits(a), vb = visits(b);
  // The whole routes traded.
  auto whole_a = Mapped(d, b, taken[b], 0, taken[b].size(), a);
  auto whole_b = Mapped(d, a, taken[a], 0, taken[a].size(), b);
  if (whole_a && whole_b && (*whole_a != taken[a] || *whole_b != taken[b])) {
    Scripts round(taken.begin(), taken.end());
    round[a] = std::move(*whole_a);
    round[b] = std::move(*whole_b);
    out.push_back(std::move(round));
  }
  for (std::size_t i = 0; i < va.size(); ++i)
    for (std::size_t j = 0; j < vb.size(); ++j) {
      if (va[i] != vb[j] || (i == 0 && j == 0)) continue;
      auto head_a = Mapped(d, b, taken[b], 0, j, a), tail_a = Mapped(d, a, taken[a], i, va.size() - 1, a);
      auto head_b = Mapped(d, a, taken[a], 0, i, b), tail_b = Mapped(d, b, taken[b], j, vb.size() - 1, b);
      if (!head_a || !head_b) continue;
      Scripts round(taken.begin(), taken.end());
      head_a->insert(head_a->end(), tail_a->begin(), tail_a->end());
      head_b->insert(head_b->end(), tail_b->begin(), tail_b->end());
      if (*head_a == taken[a] && *head_b == taken[b]) continue;
      round[a] = std::move(*head_a);
      round[b] = std::move(*head_b);
      out.push_back(std::move(round));
    }
}

// The rounds on a plan, in order: re-timing (every automaton held), the splices of every pair,
// then by the order of their last moves each automaton set free alone followed by its pairs
// with those after it (two automata that swap tasks). Pairs among the first kPairPool only.
std::vector<Scripts> Rounds(const Domain& d, const Trajectory& plan) {
  const std::size_t na = d.automata.size();
  const std::vector<std::vector<int>> taken = TransitionsTaken(plan, na);
  const Scripts held(taken.begin(), taken.end());
  const std::vector<int> order = ByLastMove(plan, na);
  const std::size_t pool = std::min(order.size(), kPairPool);
  std::vector<Scripts> out = {held};
  for (std::size_t i = 0; i < pool; ++i)
    for (std::size_t j = i + 1; j < pool; ++j) Splices(d, plan, taken, order[i], order[j], out);
  auto freeing = [&](std::vector<int> which) {
    Scripts round = held;
    for (int a : which) round[a].reset();
    out.push_back(std::move(round));
  };
  for (std::size_t i = 0; i < order.size(); ++i) {
    freeing({order[i]});
    for (std::size_t j = i + 1; i < pool && j < pool; ++j) freeing({order[i], order[j]});
  }
  return out;
}

}  // namespace

std::vector<std::vector<int>> TransitionsTaken(const Trajectory& plan, std::size_t automata) {
  std::vector<FiredTransition> fired = plan.fired;
  std::stable_sort(fired.begin(), fired.end(),
                   [](const auto& x, const auto& y) { return x.event < y.event; });
  std::vector<std::vector<int>> out(automata);
  for (const auto& f : fired) out[f.automaton].push_back(f.transition);
  return out;
}

NeighbourhoodResult ImproveByNeighbourhoods(const Domain& d, const StatePlan& sp,
                                            const Trajectory& plan, long cost, long makespan,
                                            const NeighbourhoodOptions& o) {
  const auto t0 = Clock::now();
  auto elapsed = [&] {
    return std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0).count();
  };
  NeighbourhoodResult r;
  const std::size_t na = d.automata.size();
  Trajectory current = plan;
  Value value = ValueOf(o.objective, cost, makespan);
  std::vector<Scripts> rounds = Rounds(d, current);
  bool done = plan.history != nullptr || (o.good_enough && o.good_enough(cost, makespan));
  // Re-timing keeps every transition, and so the cost: it is skipped under `cost`.
  std::size_t next = o.objective == Objective::kCost ? 1 : 0;
  while (!done && next < rounds.size()) {
    const long left = o.time_limit_ms - elapsed();
    if (left <= 0 || (o.cancel && o.cancel->load())) break;
    FirstPlanOptions fo;
    fo.objective = o.objective;
    fo.time_limit_ms = std::min(left, std::max(kMinRoundMs, o.time_limit_ms / kRoundShare));
    fo.max_events = o.max_events;
    fo.cancel = o.cancel;
    fo.good_enough = o.good_enough;
    fo.better_than = value;
    fo.scripts = rounds[next];
    FirstPlanResult round = FindFirstPlan(d, sp, fo);
    ++r.rounds;
    if (!round.best || !(ValueOf(o.objective, round.cost, round.makespan) < value)) {
      ++next;
      continue;
    }
    // A better plan: the rounds start again from it, re-timing first (after a re-timing, with the
    // next round).
    const bool retimed = next == 0;
    ++r.improved;
    current = std::move(*round.best);
    value = ValueOf(o.objective, round.cost, round.makespan);
    r.best = current;
    r.cost = round.cost;
    r.makespan = round.makespan;
    if (o.on_plan) o.on_plan(current, round.cost, round.makespan);
    done = o.good_enough && o.good_enough(round.cost, round.makespan);
    rounds = Rounds(d, current);
    next = retimed || o.objective == Objective::kCost ? 1 : 0;
  }
  r.elapsed_ms = elapsed();
  return r;
}

}  // namespace ctb
