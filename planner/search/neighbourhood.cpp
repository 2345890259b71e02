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
// Then triples among the first this many (the last rounds: a third automaton set free where two
// could not reorder their turns).
constexpr std::size_t kTriplePool = 6;
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

// A round: the scripts it holds automata to (nullopt: free), and the plan's event of each
// scripted transition (the order in which held automata take turns, FirstPlanOptions).
struct Round {
  std::vector<std::optional<std::vector<int>>> scripts;
  std::vector<std::vector<int>> ranks;
};

// Each automaton's transitions in the plan and the events they fire at.
struct Taken {
  std::vector<std::vector<int>> transitions, events;
};

Taken TakenIn(const Trajectory& plan, std::size_t automata) {
  std::vector<FiredTransition> fired = plan.fired;
  std::stable_sort(fired.begin(), fired.end(),
                   [](const auto& x, const auto& y) { return x.event < y.event; });
  Taken t;
  t.transitions.resize(automata);
  t.events.resize(automata);
  for (const auto& f : fired) {
    t.transitions[f.automaton].push_back(f.transition);
    t.events[f.automaton].push_back(f.event);
  }
  return t;
}

Round Held(const Taken& t) {
  return {{t.transitions.begin(), t.transitions.end()}, t.events};
}

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

// Steps from..to of automaton a's route appended to `out`, written as automaton b's (with their
// ranks); false when b lacks one of the transitions.
bool Append(const Domain& d, const Taken& t, int a, std::size_t from, std::size_t to, int b,
            std::vector<int>& out, std::vector<int>& ranks) {
  for (std::size_t i = from; i < to; ++i) {
    const int k = a == b ? t.transitions[a][i] : SameIn(d, a, t.transitions[a][i], b);
    if (k < 0) return false;
    out.push_back(k);
    ranks.push_back(t.events[a][i]);
  }
  return true;
}

// The round in which automaton a takes b's first j steps then its own from step i, and b takes
// a's first i then its own from j (i = j = the route's length: the whole routes traded).
std::optional<Round> Spliced(const Domain& d, const Taken& t, int a, int b, std::size_t i,
                             std::size_t j) {
  Round r = Held(t);
  std::vector<int> ra, rb, ka, kb;
  const std::size_t na = t.transitions[a].size(), nb = t.transitions[b].size();
  const bool whole = i == na && j == nb;
  if (!Append(d, t, b, 0, j, a, ra, ka) || !Append(d, t, a, 0, i, b, rb, kb)) return std::nullopt;
  if (!whole && (!Append(d, t, a, i, na, a, ra, ka) || !Append(d, t, b, j, nb, b, rb, kb)))
    return std::nullopt;
  if (ra == t.transitions[a] && rb == t.transitions[b]) return std::nullopt;
  r.scripts[a] = std::move(ra);
  r.scripts[b] = std::move(rb);
  r.ranks[a] = std::move(ka);
  r.ranks[b] = std::move(kb);
  return r;
}

// The rounds that re-time a plan whose automata a and b trade their whole routes, or the starts
// of their routes at a location both pass through (one opens the door the other waited at):
// every automaton held to its script.
void Splices(const Domain& d, const Trajectory& plan, const Taken& t, int a, int b,
             std::vector<Round>& out) {
  if (d.automata[a].locations[plan.locations[a][0]] != d.automata[b].locations[plan.locations[b][0]])
    return;
  // The location before each step of a route, and the last.
  auto visits = [&](int x) {
    std::vector<std::string> v = {d.automata[x].locations[plan.locations[x][0]]};
    for (int ti : t.transitions[x])
      v.push_back(d.automata[x].locations[d.automata[x].transitions[ti].to]);
    return v;
  };
  const std::vector<std::string> va = visits(a), vb = visits(b);
  if (auto r = Spliced(d, t, a, b, va.size() - 1, vb.size() - 1)) out.push_back(std::move(*r));
  for (std::size_t i = 0; i < va.size(); ++i)
    for (std::size_t j = 0; j < vb.size(); ++j) {
      if (va[i] != vb[j] || (i == 0 && j == 0) || (i + 1 == va.size() && j + 1 == vb.size()))
        continue;
      if (auto r = Spliced(d, t, a, b, i, j)) out.push_back(std::move(*r));
    }
}

// The rounds on a plan, in order: re-timing (every automaton held), the splices of every pair,
// then by the order of their last moves each automaton set free alone followed by its pairs
// with those after it (two automata that swap tasks), then triples. Pairs among the first
// kPairPool only, triples among the first kTriplePool.
std::vector<Round> Rounds(const Domain& d, const Trajectory& plan) {
  const std::size_t na = d.automata.size();
  const Taken taken = TakenIn(plan, na);
  const std::vector<int> order = ByLastMove(plan, na);
  const std::size_t pool = std::min(order.size(), kPairPool);
  std::vector<Round> out = {Held(taken)};
  for (std::size_t i = 0; i < pool; ++i)
    for (std::size_t j = i + 1; j < pool; ++j) Splices(d, plan, taken, order[i], order[j], out);
  auto freeing = [&](std::vector<int> which) {
    Round round = Held(taken);
    for (int a : which) round.scripts[a].reset();
    out.push_back(std::move(round));
  };
  for (std::size_t i = 0; i < order.size(); ++i) {
    freeing({order[i]});
    for (std::size_t j = i + 1; i < pool && j < pool; ++j) freeing({order[i], order[j]});
  }
  const std::size_t triples = std::min(order.size(), kTriplePool);
  for (std::size_t i = 0; i < triples; ++i)
    for (std::size_t j = i + 1; j < triples; ++j)
      for (std::size_t k = j + 1; k < triples; ++k) freeing({order[i], order[j], order[k]});
  return out;
}

}  // namespace

std::vector<std::vector<int>> TransitionsTaken(const Trajectory& plan, std::size_t automata) {
  return TakenIn(plan, automata).transitions;
}

NeighbourhoodResult ImproveByNeighbourhoods(const Domain& d, const StatePlan& sp,
                                            const Trajectory& plan, long cost, long makespan,
                                            const NeighbourhoodOptions& o) {
  const auto t0 = Clock::now();
  auto elapsed = [&] {
    return std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0).count();
  };
  NeighbourhoodResult r;
  Trajectory current = plan;
  Value value = ValueOf(o.objective, cost, makespan);
  std::vector<Round> rounds = Rounds(d, current);
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
    fo.scripts = rounds[next].scripts;
    fo.script_ranks = rounds[next].ranks;
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
