#include "planner/replan/precheck.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "planner/analyze/analyze.h"
#include "planner/expr/expr_print.h"

namespace ctb::replan {

namespace {

// a - b, saturated at the range of long: history times may be at its ends (found by the replan
// fuzz target: a time of -2^63 made h.time(k) - t0 overflow).
long Minus(long a, long b) {
  long r;
  if (__builtin_sub_overflow(a, b, &r)) return a > b ? std::numeric_limits<long>::max() : std::numeric_limits<long>::min();
  return r;
}

std::string Secs(long ticks, long tps) {
  if (tps == 1) return std::to_string(ticks);
  return Json(static_cast<double>(ticks) / static_cast<double>(tps)).dump();
}
Json SecsJson(long ticks, long tps) {
  if (tps == 1) return ticks;
  return static_cast<double>(ticks) / static_cast<double>(tps);
}
long Ticks(double seconds, long tps) { return std::lround(seconds * static_cast<double>(tps)); }

// The accepting automaton a condition may read about itself (an episode's or temporal
// constraint's own state), with the value it has on the stages scanned.
struct Self {
  VarKind kind = VarKind::kUnresolved;
  int index = -1;
  int state = 0;  // 0 waiting, 1 active, 2 accepted
};

// Only conditions over locations at [i]/[i+1] (and the part's own state) are evaluated.
bool Evaluable(const Condition& c, const Self& self = {}) {
  const ExprInfo& i = c.raw_info;
  if (i.uses_fixed || !i.commands_read.empty()) return false;
  for (int e : i.episodes_read)
    if (self.kind != VarKind::kEpisodeState || e != self.index) return false;
  for (int q : i.temporals_read)
    if (self.kind != VarKind::kTemporalState || q != self.index) return false;
  return true;
}

class HistoryView {
 public:
  explicit HistoryView(const History& h) : h_(h), p_(h.events()) {}
  int p() const { return p_; }
  long time(int k) const { return h_.times[k]; }

  // A condition at event k (contract: "When a condition holds"); Evaluable conditions only.
  bool AtEvent(const Condition& c, int k, const Self& self = {}) const {
    const bool change = c.raw_info.IsChange();
    if (change && k == 0) return false;
    return Evaluate(c.raw, [&](const Expr& atom) {
      if (atom.var_kind == VarKind::kEpisodeState || atom.var_kind == VarKind::kTemporalState)
        return k == 0 ? 0 : self.state;
      int stage = change && atom.index.kind == IndexKind::kI ? k - 1 : k;
      return h_.locations[atom.target][stage];
    });
  }
  bool OnStage(const Condition& c, int k, const Self& self = {}) const {
    return Evaluate(c.raw, [&](const Expr& atom) {
      if (atom.var_kind == VarKind::kEpisodeState || atom.var_kind == VarKind::kTemporalState)
        return self.state;
      return h_.locations[atom.target][k];
    });
  }

 private:
  const History& h_;
  int p_;
};

std::string PartPointer(const Condition& c) { return c.pointer.substr(0, c.pointer.rfind('/')); }

// What the history says about one episode or temporal constraint.
struct PartHistory {
  bool known = false;      // its conditions could be evaluated
  int first = -1;          // the event that activated it; -1: not begun by now
  bool done = false;       // it can be accepted within the history
  bool open_now = false;   // begun, not done, and still able to end in the future
  const Condition* other = nullptr;  // temporal: the condition still to come
  std::optional<ExplanationConflict> broken;  // the conflict, when the history broke it
};

ExplanationConflict Conflict(const std::string& pointer, const std::string& text, long at, long tps) {
  return {{pointer}, text, SecsJson(at, tps)};
}

PartHistory TemporalHistory(const Temporal& tc, int q, const HistoryView& h, const Situation& s) {
  PartHistory r;
  const Self waiting{VarKind::kTemporalState, q, 0}, active{VarKind::kTemporalState, q, 1};
  if (!Evaluable(tc.event1, waiting) || !Evaluable(tc.event2, waiting)) return r;
  r.known = true;
  const int p = h.p();
  const long now = s.history.now, tps = s.tps;
  for (int k = 0; k <= p && r.first < 0; ++k)
    if (h.AtEvent(tc.event1, k, waiting) || h.AtEvent(tc.event2, k, waiting)) r.first = k;
  if (r.first < 0) return r;
  const std::string ptr = PartPointer(tc.event1), name = "temporal constraint '" + tc.name + "'";
  const bool c1 = h.AtEvent(tc.event1, r.first, waiting), c2 = h.AtEvent(tc.event2, r.first, waiting);
  const long lo = Ticks(tc.lower, tps), up = Ticks(tc.upper, tps), t0 = h.time(r.first);
  if (c1 && c2) {
    r.done = tc.lower == 0;
    if (!r.done)
      r.broken = Conflict(ptr, name + " was broken at t = " + Secs(t0, tps) +
                                   " s: both its events happened at once, and its lower bound is " +
                                   Secs(lo, tps) + " s",
                          t0, tps);
    return r;
  }
  r.other = c1 ? &tc.event2 : &tc.event1;
  for (int k = r.first + 1; k <= p && !r.done; ++k)
    r.done = h.AtEvent(*r.other, k, active) && Minus(h.time(k), t0) >= lo && Minus(h.time(k), t0) <= up;
  if (r.done) return r;
  if (Minus(now, t0) <= up) {
    r.open_now = true;
    return r;
  }
  r.broken = Conflict(ptr, name + " was broken at t = " + Secs(t0 + up, tps) + " s: its " +
                               (c1 ? "first" : "second") + " event happened at t = " + Secs(t0, tps) +
                               " s and its " + (c1 ? "second" : "first") +
                               " had not come by its upper bound of " + Secs(up, tps) +
                               " s after it (now is " + Secs(now, tps) + " s)",
                      t0 + up, tps);
  return r;
}

PartHistory EpisodeHistory(const Episode& ep, int e, const HistoryView& h, const Situation& s) {
  PartHistory r;
  const Self waiting{VarKind::kEpisodeState, e, 0}, active{VarKind::kEpisodeState, e, 1};
  if (!Evaluable(ep.accepting, waiting) || !Evaluable(ep.state, active)) return r;
  r.known = true;
  const int p = h.p();
  const long now = s.history.now, tps = s.tps;
  for (int k = 0; k <= p && r.first < 0; ++k)
    if (h.AtEvent(ep.accepting, k, waiting)) r.first = k;
  if (r.first < 0) return r;
  const long lo = Ticks(ep.lower, tps), up = Ticks(ep.upper, tps), t0 = h.time(r.first);
  int fail = -1;
  for (int k = r.first; k <= p && fail < 0 && !r.done; ++k) {
    if (k > r.first && Minus(h.time(k), t0) >= lo && Minus(h.time(k), t0) <= up) r.done = true;  // may end at k
    else if (!h.OnStage(ep.state, k, active)) fail = k;
  }
  if (r.done) return r;
  const std::string ptr = PartPointer(ep.accepting), name = "episode '" + ep.name + "'";
  if (fail >= 0) {
    r.broken = Conflict(ptr, name + " was broken at t = " + Secs(h.time(fail), tps) +
                                 " s: it started at t = " + Secs(t0, tps) +
                                 " s and its state constraint stopped holding before it could "
                                 "last its lower bound of " + Secs(lo, tps) + " s",
                        h.time(fail), tps);
  } else if (Minus(now, t0) > up) {
    r.broken = Conflict(ptr, name + " was broken at t = " + Secs(t0 + up, tps) + " s: it started at t = " +
                                 Secs(t0, tps) + " s and had not ended by its upper bound of " +
                                 Secs(up, tps) + " s (now is " + Secs(now, tps) + " s)",
                        t0 + up, tps);
  } else {
    r.open_now = true;
  }
  return r;
}

}  // namespace

std::vector<ExplanationConflict> BrokenByHistory(const StatePlan& sp, const Situation& s) {
  std::vector<ExplanationConflict> out;
  const HistoryView h(s.history);
  for (std::size_t q = 0; q < sp.temporals.size(); ++q)
    if (auto r = TemporalHistory(sp.temporals[q], static_cast<int>(q), h, s); r.broken)
      out.push_back(*r.broken);
  for (std::size_t e = 0; e < sp.episodes.size(); ++e)
    if (auto r = EpisodeHistory(sp.episodes[e], static_cast<int>(e), h, s); r.broken)
      out.push_back(*r.broken);
  if (Evaluable(sp.maintenance))
    for (int k = 0; k < h.p(); ++k)
      if (!h.OnStage(sp.maintenance, k)) {
        out.push_back(Conflict(sp.maintenance.pointer, "the maintenance constraint was broken at t = " +
                                                           Secs(h.time(k), s.tps) + " s",
                               h.time(k), s.tps));
        break;
      }
  return out;
}

namespace {

Condition TrueCondition(const Condition& like) {
  Condition c;
  c.text = "true";
  c.pointer = like.pointer;
  return c;  // Expr{} is `true`
}

bool ReadsAny(const Condition& c, const std::vector<bool>& eps, const std::vector<bool>& tcs) {
  for (int e : c.info.episodes_read)
    if (eps[e]) return true;
  for (int q : c.info.temporals_read)
    if (tcs[q]) return true;
  return false;
}

// The remaining problem from the state at now, with its time origin at `origin` (ticks): the
// goal; parts not begun as they are; a begun part that must still end in the future restarted at
// the origin with its bounds shortened by the time it has already run (an episode only when its
// accepting condition is a state that holds at now); other begun parts made trivially true.
// Every future of the real problem, shifted by -origin, is a run of it (docs/replanning.md).
// nullopt when it cannot be stated (the goal reads more than locations). `floor` gets the
// makespan every begun part needs (its start plus its lower bound).
std::optional<StatePlan> Remaining(const StatePlan& sp, const Situation& s, long origin,
                                   long& floor) {
  if (!Evaluable(sp.goal)) return std::nullopt;
  StatePlan r = sp;
  const int p = s.history.events();
  // Nothing happened and now is 0: the original problem itself. With now > 0 a part whose
  // condition held at stage 0 began at time 0, not at the origin: it is handled below like any
  // begun part (taken as beginning at now, the bound would exceed plans that exist).
  if (p == 0 && s.history.now == 0) return r;
  for (std::size_t a = 0; a < r.initial.size(); ++a) r.initial[a] = s.history.locations[a][p];
  const HistoryView h(s.history);
  const long tps = s.tps;
  std::vector<bool> trivial_ep(sp.episodes.size(), false), trivial_tc(sp.temporals.size(), false);
  bool changed = false;
  for (std::size_t e = 0; e < sp.episodes.size(); ++e) {
    Episode& ep = r.episodes[e];
    PartHistory ph = EpisodeHistory(sp.episodes[e], static_cast<int>(e), h, s);
    if (ph.known && ph.first < 0) continue;
    changed = true;
    const long t0 = ph.first >= 0 ? h.time(ph.first) : 0;
    if (ph.first >= 0) floor = std::max(floor, t0 + Ticks(sp.episodes[e].lower, tps));
    const bool restart = ph.open_now && !sp.episodes[e].accepting.raw_info.IsChange() &&
                         h.AtEvent(sp.episodes[e].accepting, p, {VarKind::kEpisodeState, static_cast<int>(e), 0});
    if (restart) {
      const double ran = static_cast<double>(origin - t0) / static_cast<double>(tps);
      ep.lower = std::max(0.0, ep.lower - ran);
      ep.upper = ep.upper - ran;
      if (ep.upper >= ep.lower) continue;
    }
    trivial_ep[e] = true;
    ep.accepting = TrueCondition(ep.accepting);
    ep.state = TrueCondition(ep.state);
    ep.lower = 0;
    ep.upper = 1e9;
  }
  for (std::size_t q = 0; q < sp.temporals.size(); ++q) {
    Temporal& tc = r.temporals[q];
    PartHistory ph = TemporalHistory(sp.temporals[q], static_cast<int>(q), h, s);
    if (ph.known && ph.first < 0) continue;
    changed = true;
    if (ph.first >= 0)
      floor = std::max(floor, h.time(ph.first) + Ticks(sp.temporals[q].lower, tps));
    // Restarted: active from the origin, accepted when the other condition comes (not when it
    // already holds at now, where the restarted form would read both at once).
    const Self active{VarKind::kTemporalState, static_cast<int>(q), 1};
    if (ph.open_now && ph.other && !h.AtEvent(*ph.other, p, active)) {
      const double ran = static_cast<double>(origin - h.time(ph.first)) / static_cast<double>(tps);
      const Condition other = *ph.other;
      tc.event1 = TrueCondition(tc.event1);
      tc.event2 = other;
      tc.lower = std::max(0.0, tc.lower - ran);
      tc.upper = tc.upper - ran;
      if (tc.upper >= tc.lower) continue;
    }
    trivial_tc[q] = true;
    tc.event1 = TrueCondition(tc.event1);
    tc.event2 = TrueCondition(tc.event2);
    tc.lower = 0;
    tc.upper = 1e9;
  }
  if (!changed) return r;
  // Shared events and the maintenance constraint are dropped (a relaxation); a kept condition
  // must not read a part made trivial.
  r.events.clear();
  r.maintenance = TrueCondition(sp.maintenance);
  for (const auto& ep : r.episodes)
    if (ReadsAny(ep.accepting, trivial_ep, trivial_tc) || ReadsAny(ep.state, trivial_ep, trivial_tc))
      return std::nullopt;
  for (const auto& tc : r.temporals)
    if (ReadsAny(tc.event1, trivial_ep, trivial_tc) || ReadsAny(tc.event2, trivial_ep, trivial_tc))
      return std::nullopt;
  return r;
}

// The goal alone from the state at now.
std::optional<StatePlan> GoalOnly(const StatePlan& sp, const Situation& s) {
  if (!Evaluable(sp.goal)) return std::nullopt;
  StatePlan r = sp;
  const int p = s.history.events();
  for (std::size_t a = 0; a < r.initial.size(); ++a) r.initial[a] = s.history.locations[a][p];
  r.episodes.clear();
  r.temporals.clear();
  r.events.clear();
  r.maintenance = TrueCondition(sp.maintenance);
  return r;
}

}  // namespace

std::optional<ExplanationConflict> GoalCutOff(const Domain& d, const StatePlan& sp,
                                              const Situation& s) {
  auto r = GoalOnly(sp, s);
  if (!r) return std::nullopt;
  auto conflict = [&](const Domain& dom) {
    for (const auto& c : FindStaticConflicts(dom, *r, AnalysisOptions{.clocks_at_zero = false}))
      if (std::find(c.parts.begin(), c.parts.end(), sp.goal.pointer) != c.parts.end()) return true;
    return false;
  };
  if (!conflict(s.analysis_domain)) return std::nullopt;
  std::vector<std::string> pointers = {sp.goal.pointer};
  std::string text;
  Domain model, analysis;
  BlockedDomains(d, {}, model, analysis);
  if (conflict(analysis)) {
    text = "the goal can no longer be reached from where the automata are at t = " +
           Secs(s.history.now, s.tps) + " s";
  } else {
    // A minimal set of blocked entries that still cuts the goal off (deletion, in order).
    std::vector<Blocked> cut = s.blocked;
    for (std::size_t i = 0; i < cut.size();) {
      std::vector<Blocked> without = cut;
      without.erase(without.begin() + static_cast<long>(i));
      BlockedDomains(d, without, model, analysis);
      if (conflict(analysis)) cut = without;
      else ++i;
    }
    text = "the goal can no longer be reached from where the automata are at t = " +
           Secs(s.history.now, s.tps) + " s without the blocked transition" +
           (cut.size() > 1 ? "s" : "") + " ";
    for (std::size_t i = 0; i < cut.size(); ++i) {
      const Blocked& b = cut[i];
      const Automaton& au = d.automata[b.automaton];
      const Transition& t = au.transitions[b.transitions[0]];
      text += (i ? (i + 1 == cut.size() ? " and " : ", ") : "") + au.name + " " +
              au.locations[t.from] + " -> " + au.locations[t.to] + " (" + b.pointer + ")";
      pointers.push_back(b.pointer);
    }
  }
  return ExplanationConflict{pointers, text, Json()};
}

ObjectiveBounds HistoryBounds(const StatePlan& sp, const Situation& s) {
  const History& h = s.history;
  const int p = h.events();
  ObjectiveBounds b;
  b.cost = s.history_cost;
  b.makespan_ticks = h.times[p];
  b.events = p;
  // The end state may be accepted at event p (the future empty) when the goal holds there and
  // every part may have been accepted in the history: then only the history's bounds hold.
  if (!Evaluable(sp.goal)) return b;
  const HistoryView view(h);
  if (view.AtEvent(sp.goal, p)) {
    bool all_done = true;
    for (std::size_t e = 0; e < sp.episodes.size(); ++e) {
      PartHistory ph = EpisodeHistory(sp.episodes[e], static_cast<int>(e), view, s);
      all_done = all_done && (!ph.known || ph.done);
    }
    for (std::size_t q = 0; q < sp.temporals.size(); ++q) {
      PartHistory ph = TemporalHistory(sp.temporals[q], static_cast<int>(q), view, s);
      all_done = all_done && (!ph.known || ph.done);
    }
    if (all_done) return b;
  }
  // The remaining problem starts at now. A transition from a location held at now fires no
  // earlier than max(entry + lo, now): in the domain the bounds read, its lower duration is what
  // is left of it at now (docs/replanning.md).
  const long origin = h.now;
  Domain bd = s.analysis_domain;
  for (std::size_t a = 0; a < h.entry.size(); ++a)
    for (Transition& t : bd.automata[a].transitions)
      if (t.from == h.locations[a][p])
        t.duration.lo = std::max(0.0, t.duration.lo - static_cast<double>(h.now - h.entry[a][p]) /
                                                          static_cast<double>(s.tps));
  long floor = 0;
  auto r = Remaining(sp, s, origin, floor);
  if (!r) r = GoalOnly(sp, s);
  if (!r) return b;
  const ObjectiveBounds rest = LowerBounds(bd, *r);
  b.cost += rest.cost;
  b.events += std::max(1L, rest.events);  // the goal does not hold at now: g > p
  b.makespan_ticks = std::max({b.makespan_ticks, h.now, floor, origin + rest.makespan_ticks});
  return b;
}

}  // namespace ctb::replan
