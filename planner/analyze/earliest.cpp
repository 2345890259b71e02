#include "planner/analyze/earliest.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <queue>
#include <utility>

#include "planner/expr/normalize.h"

namespace ctb {

namespace {

constexpr long kNever = EarliestTimes::kNever;

long Add(long a, long b) { return std::min(kNever, a + b); }

long Ticks(double seconds, long tps) { return std::lround(seconds * static_cast<double>(tps)); }

using AtomBound = std::function<long(const Expr&)>;

// The earliest time e can hold when each atom holds no earlier than `atom` says. What it cannot
// bound (negations, implications, true) counts as 0: a lower bound must never overshoot.
long EarliestOf(const Expr& e, const AtomBound& atom) {
  switch (e.op) {
    case Expr::Op::kFalse: return kNever;
    case Expr::Op::kAtom: return atom(e);
    case Expr::Op::kAnd:
      return std::max(EarliestOf(e.kids[0], atom), EarliestOf(e.kids[1], atom));
    case Expr::Op::kOr:
      return std::min(EarliestOf(e.kids[0], atom), EarliestOf(e.kids[1], atom));
    default: return 0;
  }
}

bool PositiveLocation(const Expr& e) {
  return e.op == Expr::Op::kAtom && e.var_kind == VarKind::kLocation && !e.not_equal &&
         e.index.kind != IndexKind::kFixed;
}

std::vector<std::pair<int, int>> Pinned(const Expr& e) {
  std::vector<std::pair<int, int>> out;
  RequiredLocations(e, out);
  return out;
}

// True when e's top-level conjunction needs temporal constraint q active or accepted (its state
// at the stage before the event is 1 or 2), so the event comes strictly after q's first event.
bool NeedsOwnActive(const Expr& e, int q) {
  std::vector<const Expr*> parts;
  Flatten(e, Expr::Op::kAnd, parts);
  for (const Expr* p : parts)
    if (p->op == Expr::Op::kAtom && p->var_kind == VarKind::kTemporalState && p->target == q &&
        !p->not_equal && (p->value_code == 1 || p->value_code == 2))
      return true;
  return false;
}

// [automaton][from][to]: least lower durations, guards ignored.
using Distances = std::vector<std::vector<std::vector<long>>>;

// A guard that is a conjunction of atoms (and true), as its atoms; false for any other shape.
bool ConjunctionAtoms(const Expr& e, std::vector<const Expr*>& out) {
  switch (e.op) {
    case Expr::Op::kTrue: return true;
    case Expr::Op::kAtom: out.push_back(&e); return true;
    case Expr::Op::kAnd: return ConjunctionAtoms(e.kids[0], out) && ConjunctionAtoms(e.kids[1], out);
    default: return false;
  }
}

// [automaton][transition]: the guard's atoms when it is such a conjunction (`flat`), so that
// SettleArrivals reads it without walking the tree.
struct FlatGuard {
  bool flat = false;
  std::vector<const Expr*> atoms;
};
using FlatGuards = std::vector<std::vector<FlatGuard>>;

class Earliest {
 public:
  Earliest(const Domain& d, const StatePlan& sp, Measure measure)
      : d_(d), sp_(sp), tps_(std::max(1L, std::lround(1.0 / d.time_resolution))),
        events_(measure == Measure::kEvents), start_(sp.initial) {}

  // From a state under way (RemainingTime): each automaton in `loc` since `since` ticks; time
  // 0 is now, and no transition fires before it.
  Earliest(const Domain& d, const StatePlan& sp, const std::vector<int>& loc,
           const std::vector<long>& since, const Distances& dist, const FlatGuards& flat)
      : d_(d), sp_(sp), tps_(std::max(1L, std::lround(1.0 / d.time_resolution))), events_(false),
        start_(loc), since_(&since), dist_(&dist), flat_(&flat) {}

  // The goal and the helpers' return from the state under way (no state-plan network).
  long GoalFromState() {
    ComputeDwell();  // none: RemainingTime::Applies leaves no episode
    if (!SettleArrivals()) return 0;
    return std::max(GoalTime(), HelperReturnTime());
  }

  std::optional<EarliestTimes> Run() {
    ComputeDwell();
    if (!SettleArrivals()) return std::nullopt;
    SettleStatePlan();
    EarliestTimes out;
    out.arrival = arr_;
    out.goal = std::max({GoalTime(), ReturnTime(), HelperReturnTime()});
    return out;
  }

 private:
  // An episode that starts exactly when a enters l and holds a in l keeps a there, from its first
  // entry, for at least its lower bound.
  void ComputeDwell() {
    dwell_.resize(d_.automata.size());
    for (std::size_t a = 0; a < d_.automata.size(); ++a)
      dwell_[a].assign(d_.automata[a].locations.size(), 0);
    if (events_) return;
    for (const Episode& ep : sp_.episodes) {
      const Expr& acc = ep.accepting.expr;
      if (ep.accepting.info.IsChange() || !PositiveLocation(acc)) continue;
      for (auto [a, l] : Pinned(ep.state.expr))
        if (a == acc.target && l == acc.value_code)
          dwell_[a][l] = std::max(dwell_[a][l], Ticks(ep.lower, tps_));
    }
  }

  // A transition's least length: its lower duration, or one event.
  long Duration(const Transition& t) const { return events_ ? 1 : Ticks(t.duration.lo, tps_); }

  // a == l holds once a has entered l; a != l once a has entered some other location (a
  // starting elsewhere: at once).
  long LocationAtom(const Expr& atom) const {
    if (atom.var_kind != VarKind::kLocation || atom.index.kind == IndexKind::kFixed) return 0;
    const std::vector<long>& arr = arr_[atom.target];
    if (!atom.not_equal) return arr[atom.value_code];
    if (!least_.empty()) {  // the two least arrivals of the round (SettleArrivals)
      const Least& m = least_[atom.target];
      return m.at == atom.value_code ? m.second : m.first;
    }
    long first = kNever;
    for (std::size_t l = 0; l < arr.size(); ++l)
      if (static_cast<int>(l) != atom.value_code) first = std::min(first, arr[l]);
    return first;
  }

  long GuardTime(std::size_t a, std::size_t ti, const AtomBound& atom) const {
    if (flat_) {
      const FlatGuard& g = (*flat_)[a][ti];
      if (g.flat) {
        long t = 0;
        for (const Expr* e : g.atoms) t = std::max(t, LocationAtom(*e));
        return t;
      }
    }
    return EarliestOf(d_.automata[a].transitions[ti].guard, atom);
  }

  // Per automaton the least arrival (and where) and the second least: "a != l" in one step.
  struct Least {
    long first = kNever, second = kNever;
    int at = -1;
  };
  void ComputeLeast() {
    least_.assign(arr_.size(), Least{});
    for (std::size_t a = 0; a < arr_.size(); ++a) {
      Least& m = least_[a];
      for (std::size_t l = 0; l < arr_[a].size(); ++l) {
        const long v = arr_[a][l];
        if (v < m.first) {
          m.second = m.first, m.first = v, m.at = static_cast<int>(l);
        } else if (v < m.second) {
          m.second = v;
        }
      }
    }
  }

  // First entries, settled from above (Bellman-Ford rounds): a transition from l fires no earlier
  // than l's first entry plus its lower duration and l's dwell, nor before its guard can hold.
  // A settled vector satisfies every rule, which is what the argument needs.
  bool SettleArrivals() {
    std::size_t nodes = 0;
    arr_.resize(d_.automata.size());
    for (std::size_t a = 0; a < d_.automata.size(); ++a) {
      arr_[a].assign(d_.automata[a].locations.size(), kNever);
      arr_[a][start_[a]] = since_ ? -(*since_)[a] : 0;
      nodes += arr_[a].size();
    }
    const AtomBound atom = [this](const Expr& e) { return LocationAtom(e); };
    for (std::size_t round = 0; round <= nodes + 1; ++round) {
      bool changed = false;
      // Guards read the round's start (values only fall, so a stale one is larger): the rounds
      // go on until one changes nothing, and the last reads the settled values.
      ComputeLeast();
      for (std::size_t a = 0; a < d_.automata.size(); ++a)
        for (std::size_t ti = 0; ti < d_.automata[a].transitions.size(); ++ti) {
          const Transition& t = d_.automata[a].transitions[ti];
          const long from = arr_[a][t.from];
          if (from >= kNever) continue;
          long fire = std::max({Add(from, Duration(t)), Add(from, dwell_[a][t.from]),
                                Add(GuardTime(a, ti, atom), events_ ? 1 : 0), 0L});
          if (fire < arr_[a][t.to]) {
            arr_[a][t.to] = fire;
            changed = true;
          }
        }
      if (!changed) {
        least_.clear();
        return true;
      }
    }
    least_.clear();
    return false;
  }

  // An atom of a state-plan condition at an event: a location is entered no later than the event
  // (at [i] of a change condition, no later than the event before); an episode (temporal
  // constraint) read as active or accepted has started (opened) or ended (been accepted).
  long EventAtom(const Expr& atom) const {
    if (atom.var_kind == VarKind::kLocation) return LocationAtom(atom);
    if (atom.not_equal) return 0;
    switch (atom.var_kind) {
      case VarKind::kEpisodeState:
        return atom.value_code == 1 ? ep_s_[atom.target] : atom.value_code == 2 ? ep_e_[atom.target] : 0;
      case VarKind::kTemporalState:
        return atom.value_code == 1 ? tc_a_[atom.target] : atom.value_code == 2 ? tc_b_[atom.target] : 0;
      default: return 0;
    }
  }

  long At(const Condition& c) const {
    return EarliestOf(c.expr, [this](const Expr& e) { return EventAtom(e); });
  }

  long& Node(const Endpoint& p) {
    switch (p.kind) {
      case EndpointKind::kEpisodeStart: return ep_s_[p.index];
      case EndpointKind::kEpisodeEnd: return ep_e_[p.index];
      case EndpointKind::kEvent1: return tc_1_[p.index];
      case EndpointKind::kEvent2: break;
    }
    return tc_2_[p.index];
  }

  // The locations c pins at its event (L[a,k]): every atom of a state condition, the [i+1] atoms
  // of a change condition. With `entered`, only those a change condition shows being entered at
  // the event (a[i]==x /\ a[i+1]==l, x != l).
  std::vector<std::pair<int, int>> PinnedAtEvent(const Condition& c, bool entered) const {
    std::vector<const Expr*> parts;
    Flatten(c.expr, Expr::Op::kAnd, parts);
    const bool change = c.info.IsChange();
    std::vector<std::pair<int, int>> now, before, out;
    for (const Expr* p : parts) {
      if (!PositiveLocation(*p)) continue;
      bool at_i = change && p->index.kind == IndexKind::kI;
      (at_i ? before : now).emplace_back(p->target, p->value_code);
    }
    if (!entered) return now;
    for (auto [a, l] : now)
      for (auto [b, x] : before)
        if (a == b && x != l) out.emplace_back(a, l);
    return out;
  }

  // When `later` holds strictly after `earlier`: the least travel from what `earlier` pins to
  // what `later` pins, per automaton. In events, from any pinned location; in time, only from a
  // location entered at the earlier event (its entry time is then that event's).
  long Travel(const Condition& earlier, const Condition& later) const {
    long best = 0;
    for (auto [a, from] : PinnedAtEvent(earlier, !events_))
      for (auto [b, to] : PinnedAtEvent(later, false))
        if (a == b && from != to) {
          long d = Distance(a, from, to);
          if (d < kNever) best = std::max(best, d);
        }
    return best;
  }

  // One round of the state plan's network; true when some time grew.
  bool Round() {
    bool changed = false;
    auto raise = [&changed](long& x, long v) {
      if (v > x) x = v, changed = true;
    };
    for (std::size_t p = 0; p < sp_.episodes.size(); ++p) {
      raise(ep_s_[p], At(sp_.episodes[p].accepting));
      raise(ep_e_[p], Add(ep_s_[p], events_ ? 1 : Ticks(sp_.episodes[p].lower, tps_)));
    }
    for (std::size_t q = 0; q < sp_.temporals.size(); ++q) {
      const Temporal& tc = sp_.temporals[q];
      raise(tc_1_[q], At(tc.event1));
      raise(tc_2_[q], At(tc.event2));
      const int qi = static_cast<int>(q);
      long open = NeedsOwnActive(tc.event2.expr, qi)   ? tc_1_[q]
                  : NeedsOwnActive(tc.event1.expr, qi) ? tc_2_[q]
                                                       : std::min(tc_1_[q], tc_2_[q]);
      raise(tc_a_[q], open);
      if (NeedsOwnActive(tc.event2.expr, qi)) raise(tc_2_[q], Add(tc_1_[q], Travel(tc.event1, tc.event2)));
      if (NeedsOwnActive(tc.event1.expr, qi)) raise(tc_1_[q], Add(tc_2_[q], Travel(tc.event2, tc.event1)));
      const long gap = events_ ? (tc.lower > 0 ? 1 : 0) : Ticks(tc.lower, tps_);
      raise(tc_b_[q], std::max({tc_1_[q], tc_2_[q], Add(tc_a_[q], gap)}));
    }
    for (const SharedEvent& ev : sp_.events) {
      long t = 0;
      for (const Endpoint& p : ev.endpoints) t = std::max(t, Node(p));
      for (const Endpoint& p : ev.endpoints) raise(Node(p), t);
    }
    return changed;
  }

  // Grown from 0 (every round keeps each time a lower bound), until nothing changes or the round
  // limit; stopping early only weakens the bound.
  void SettleStatePlan() {
    const std::size_t ne = sp_.episodes.size(), nt = sp_.temporals.size();
    ep_s_.assign(ne, 0);
    ep_e_.assign(ne, 0);
    tc_1_.assign(nt, 0);
    tc_2_.assign(nt, 0);
    tc_a_.assign(nt, 0);
    tc_b_.assign(nt, 0);
    for (std::size_t round = 0; round < 2 * (ne + 2 * nt) + 4; ++round)
      if (!Round()) break;
  }

  long GoalTime() const {
    long t = At(sp_.goal);
    for (long e : ep_e_) t = std::max(t, e);
    for (long b : tc_b_) t = std::max(t, b);
    return t;
  }

  // Least time (events) over lower durations (transitions) from entering m to entering `to`,
  // guards ignored.
  long Distance(int a, int m, int to) const {
    if (dist_) return (*dist_)[a][m][to];
    return ShortestFrom(d_.automata[a], m, [this](const Transition& t) { return Duration(t); })[to];
  }

  // An episode holds a in l' up to its end; the goal pins a to l != l', so a leaves l' no earlier
  // than the episode's end and then travels from the location it enters to l.
  long ReturnTime() const {
    if (sp_.goal.info.IsChange()) return 0;
    long best = 0;
    for (auto [a, l] : Pinned(sp_.goal.expr))
      for (std::size_t p = 0; p < sp_.episodes.size(); ++p)
        for (auto [b, held] : Pinned(sp_.episodes[p].state.expr)) {
          if (b != a || held == l) continue;
          long leave = kNever;
          for (const Transition& t : d_.automata[a].transitions)
            if (t.from == held && t.to != held) leave = std::min(leave, Distance(a, t.to, l));
          if (leave < kNever) best = std::max(best, Add(ep_e_[p], leave));
        }
    return best;
  }

  // The goal pins b to l where b does not start, so b's last entry into l is by a transition t
  // whose guard needs k in v; k was then in v (entered no earlier than its arrival there) and,
  // when the goal pins k to f, still needs the fastest way from v to f (an arm that places the
  // block must then get home). The least such time over the transitions into l.
  long HelperReturnTime() const {
    if (sp_.goal.info.IsChange()) return 0;
    const auto pins = Pinned(sp_.goal.expr);
    std::vector<int> pinned(d_.automata.size(), -1);
    for (auto [a, l] : pins) pinned[a] = l;
    long best = 0;
    for (auto [b, l] : pins) {
      if (l == start_[b]) continue;
      long entry = kNever;
      for (const Transition& t : d_.automata[b].transitions) {
        if (t.to != l || t.from == l) continue;
        long need = 0;
        for (auto [k, v] : Pinned(t.guard))
          if (k != b && pinned[k] >= 0) need = std::max(need, Add(arr_[k][v], Distance(k, v, pinned[k])));
        entry = std::min(entry, need);
      }
      if (entry < kNever) best = std::max(best, entry);
    }
    return best;
  }

  const Domain& d_;
  const StatePlan& sp_;
  const long tps_;
  const bool events_;
  const std::vector<int>& start_;         // where each automaton is at time 0
  const std::vector<long>* since_ = nullptr;  // how long it has been there (null: just entered)
  const Distances* dist_ = nullptr;           // Distance, precomputed (null: computed)
  const FlatGuards* flat_ = nullptr;          // guards as atoms, where they are conjunctions
  std::vector<std::vector<long>> dwell_, arr_;
  std::vector<Least> least_;  // during SettleArrivals only
  std::vector<long> ep_s_, ep_e_, tc_1_, tc_2_, tc_a_, tc_b_;
};

}  // namespace

void RequiredLocations(const Expr& e, std::vector<std::pair<int, int>>& out) {
  std::vector<const Expr*> parts;
  Flatten(e, Expr::Op::kAnd, parts);
  for (const Expr* p : parts)
    if (PositiveLocation(*p)) out.emplace_back(p->target, p->value_code);
}

std::vector<long> ShortestFrom(const Automaton& a, int from,
                               const std::function<long(const Transition&)>& weight) {
  std::vector<long> dist(a.locations.size(), kNever);
  using Item = std::pair<long, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> q;
  dist[from] = 0;
  q.push({0, from});
  while (!q.empty()) {
    auto [d, l] = q.top();
    q.pop();
    if (d > dist[l]) continue;
    for (const Transition& t : a.transitions) {
      const long w = Add(d, weight(t));
      if (t.from == l && w < dist[t.to]) dist[t.to] = w, q.push({w, t.to});
    }
  }
  return dist;
}

std::optional<EarliestTimes> ComputeEarliestTimes(const Domain& d, const StatePlan& sp,
                                                  Measure measure) {
  return Earliest(d, sp, measure).Run();
}

struct RemainingTime::Tables {
  Distances dist;
  FlatGuards flat;
};

RemainingTime::~RemainingTime() = default;

RemainingTime::RemainingTime(const Domain& d, const StatePlan& sp)
    : d_(d), sp_(sp), tables_(std::make_unique<Tables>()) {
  const long tps = std::max(1L, std::lround(1.0 / d.time_resolution));
  Distances& dist_ = tables_->dist;
  dist_.resize(d.automata.size());
  tables_->flat.resize(d.automata.size());
  for (std::size_t a = 0; a < d.automata.size(); ++a)
    for (const Transition& t : d.automata[a].transitions) {
      FlatGuard g;
      g.flat = ConjunctionAtoms(t.guard, g.atoms);
      tables_->flat[a].push_back(std::move(g));
    }
  for (std::size_t a = 0; a < d.automata.size(); ++a)
    for (std::size_t m = 0; m < d.automata[a].locations.size(); ++m)
      dist_[a].push_back(ShortestFrom(d.automata[a], static_cast<int>(m), [tps](const Transition& t) {
        return Ticks(t.duration.lo, tps);
      }));
}

bool RemainingTime::Applies(const StatePlan& sp) {
  return sp.episodes.empty() && sp.temporals.empty() && sp.events.empty() &&
         !sp.goal.info.IsChange();
}

long RemainingTime::Goal(const std::vector<int>& loc, const std::vector<long>& since) const {
  return Earliest(d_, sp_, loc, since, tables_->dist, tables_->flat).GoalFromState();
}

}  // namespace ctb
