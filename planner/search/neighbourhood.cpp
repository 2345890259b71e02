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
// a's first i then its own from j (i and j the routes' lengths: the whole routes traded); nullopt
// when one lacks the other's transitions or nothing changes.
std::optional<Round> Spliced(const Domain& d, const Taken& t, int a, int b, std::size_t i,
                             std::size_t j) {
  Round r = Held(t);
  std::vector<int> ra, rb, ka, kb;
  const std::size_t na = t.transitions[a].size(), nb = t.transitions[b].size();
  if (!Append(d, t, b, 0, j, a, ra, ka) || !Append(d, t, a, 0, i, b, rb, kb) ||
      !Append(d, t, a, i, na, a, ra, ka) || !Append(d, t, b, j, nb, b, rb, kb))
    return std::nullopt;
  if (ra == t.transitions[a] && rb == t.transitions[b]) return std::nullopt;
  r.scripts[a] = std::move(ra);
  r.scripts[b] = std::move(rb);
  r.ranks[a] = std::move(ka);
  r.ranks[b] = std::move(kb);
  return r;
}

// A round described: the automata set free (re-timing when none), or a splice of two (a, b at
// steps i, j). Rounds are built when they run: a team of a thousand has a thousand.
struct RoundSpec {
  std::vector<int> free;
  int a = -1, b = -1;
  std::size_t i = 0, j = 0;
};

// The splices of automata a and b: their whole routes traded, and the starts of their routes
// traded at every location both pass through (one opens the door the other waited at).
void Splices(const Domain& d, const Trajectory& plan, const Taken& t, int a, int b,
             std::vector<RoundSpec>& out) {
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
  const std::size_t la = va.size() - 1, lb = vb.size() - 1;
  out.push_back({{}, a, b, la, lb});
  for (std::size_t i = 0; i <= la; ++i)
    for (std::size_t j = 0; j <= lb; ++j)
      if (va[i] == vb[j] && !(i == 0 && j == 0) && !(i == la && j == lb))
        out.push_back({{}, a, b, i, j});
}

// The rounds on a plan, in order: re-timing (every automaton held), the splices of the pairs,
// then by the order of their last moves each automaton set free alone followed by its pairs
// with those after it (two automata that swap tasks), then triples. Splices and pairs among the
// first kPairPool only, triples among the first kTriplePool.
std::vector<RoundSpec> Rounds(const Domain& d, const Trajectory& plan, const Taken& taken) {
  const std::vector<int> order = ByLastMove(plan, d.automata.size());
  const std::size_t pool = std::min(order.size(), kPairPool);
  std::vector<RoundSpec> out = {{}};
  for (std::size_t i = 0; i < pool; ++i)
    for (std::size_t j = i + 1; j < pool; ++j) Splices(d, plan, taken, order[i], order[j], out);
  for (std::size_t i = 0; i < order.size(); ++i) {
    out.push_back({{order[i]}});
    if (i < pool)
      for (std::size_t j = i + 1; j < pool; ++j) out.push_back({{order[i], order[j]}});
  }
  const std::size_t triples = std::min(order.size(), kTriplePool);
  for (std::size_t i = 0; i < triples; ++i)
    for (std::size_t j = i + 1; j < triples; ++j)
      for (std::size_t k = j + 1; k < triples; ++k)
        out.push_back({{order[i], order[j], order[k]}});
  return out;
}

// The scripts of a round described; nullopt for a splice that changes nothing or cannot be made.
std::optional<Round> Build(const Domain& d, const Taken& taken, const RoundSpec& spec) {
  if (spec.a >= 0) return Spliced(d, taken, spec.a, spec.b, spec.i, spec.j);
  Round round = Held(taken);
  for (int a : spec.free) round.scripts[a].reset();
  return round;
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
  if (plan.history || (o.good_enough && o.good_enough(cost, makespan))) return r;
  Trajectory current = plan;
  Value value = ObjectiveKey(o.objective, cost, makespan);
  Taken taken = TakenIn(current, d.automata.size());
  std::vector<RoundSpec> rounds = Rounds(d, current, taken);
  // Re-timing keeps every transition, and so the cost: it is skipped under `cost`.
  std::size_t next = o.objective == Objective::kCost ? 1 : 0;
  while (next < rounds.size()) {
    const long left = o.time_limit_ms - elapsed();
    if (left <= 0 || (o.cancel && o.cancel->load())) break;
    std::optional<Round> round = Build(d, taken, rounds[next]);
    if (!round) {
      ++next;
      continue;
    }
    FirstPlanOptions fo;
    fo.objective = o.objective;
    fo.time_limit_ms = std::min(left, std::max(kMinRoundMs, o.time_limit_ms / kRoundShare));
    fo.max_expanded = o.round_expansions;
    fo.max_events = o.max_events;
    fo.cancel = o.cancel;
    fo.good_enough = o.good_enough;
    fo.better_than = value;
    fo.scripts = std::move(round->scripts);
    fo.script_ranks = std::move(round->ranks);
    FirstPlanResult found = FindFirstPlan(d, sp, fo);
    ++r.rounds;
    if (!found.best || !(ObjectiveKey(o.objective, found.cost, found.makespan) < value)) {
      ++next;
      continue;
    }
    // A better plan: the rounds start again from it, with re-timing (after a re-timing, with the
    // round after it: the same transitions re-timed again change nothing).
    const bool retimed = rounds[next].free.empty() && rounds[next].a < 0;
    ++r.improved;
    current = std::move(*found.best);
    value = ObjectiveKey(o.objective, found.cost, found.makespan);
    r.best = current;
    r.cost = found.cost;
    r.makespan = found.makespan;
    if (o.on_plan) o.on_plan(current, found.cost, found.makespan);
    if (o.good_enough && o.good_enough(found.cost, found.makespan)) break;
    taken = TakenIn(current, d.automata.size());
    rounds = Rounds(d, current, taken);
    next = retimed || o.objective == Objective::kCost ? 1 : 0;
  }
  r.elapsed_ms = elapsed();
  return r;
}

}  // namespace ctb
