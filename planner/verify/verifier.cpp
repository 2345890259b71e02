// Independent replay of a trajectory against the contract (sections 2 and 3). It shares only the
// parsed domain and state plan with the encoder; every rule is re-derived here from the text.
#include <algorithm>
#include <cmath>
#include <map>

#include "planner/expr/expr_print.h"
#include "planner/verify/verify.h"

namespace ctb {

namespace {

class Replay {
 public:
  Replay(const Trajectory& t, const Domain& d, const StatePlan& sp, long tps)
      : t_(t), d_(d), sp_(sp), tps_(tps), g_(t.goal_event) {}

  std::vector<std::string> Run() {
    if (!Shape()) return errors_;
    Dynamics();
    if (!Stopped()) StatePlanRules();
    return errors_;
  }

  // Stop at the first violation (TrajectoryIsPlan: brute force asks only yes or no).
  bool stop_at_first_ = false;
  bool allow_idle_ = false;

 private:
  void Fail(std::string msg) { errors_.push_back(std::move(msg)); }
  // In stop-at-first mode the rules' loops return once a violation is recorded.
  bool Stopped() const { return stop_at_first_ && !errors_.empty(); }
  long Ticks(double seconds) const { return std::lround(seconds * static_cast<double>(tps_)); }
  std::string Name(int a) const { return d_.automata[a].name; }

  bool Shape() {
    const std::size_t na = d_.automata.size();
    if (g_ < 0 || static_cast<int>(t_.events.size()) != g_ + 1) {
      Fail("events do not run from e[0] to the goal event");
      return false;
    }
    if (t_.locations.size() != na || t_.commands.size() != na) {
      Fail("one timeline per automaton expected");
      return false;
    }
    for (std::size_t a = 0; a < na; ++a)
      if (static_cast<int>(t_.locations[a].size()) != g_ + 1 ||
          static_cast<int>(t_.commands[a].size()) != g_ + 1) {
        Fail("timeline of '" + Name(a) + "' does not cover stages 0.." + std::to_string(g_));
        return false;
      }
    if (t_.episodes.size() != sp_.episodes.size() || t_.temporals.size() != sp_.temporals.size() ||
        t_.orders.size() != sp_.orders.size()) {
      Fail("episode or temporal constraint events missing");
      return false;
    }
    return HistoryShape();
  }

  // A fixed history (replanning): stages 0..p are as reported; the run must reproduce them.
  bool HistoryShape() {
    if (!t_.history) return true;
    const History& h = *t_.history;
    const int p = h.events();
    const std::size_t na = d_.automata.size();
    if (p < 0 || p > g_ || h.locations.size() != na || h.entry.size() != na) {
      Fail("the history does not fit the run (" + std::to_string(p) + " history events, goal at event " +
           std::to_string(g_) + ")");
      return false;
    }
    for (int k = 0; k <= p; ++k) {
      if (t_.events[k] != h.times[k]) Fail("event " + std::to_string(k) + " is not at its history time");
      for (std::size_t a = 0; a < na; ++a)
        if (t_.locations[a][k] != h.locations[a][k])
          Fail("'" + Name(a) + "' is not where the history has it on stage " + std::to_string(k));
    }
    std::vector<FiredTransition> mine;
    for (const auto& f : t_.fired)
      if (f.event <= p) mine.push_back(f);
    auto same = [](const FiredTransition& x, const FiredTransition& y) {
      return x.event == y.event && x.automaton == y.automaton && x.transition == y.transition;
    };
    if (mine.size() != h.fired.size() || !std::equal(mine.begin(), mine.end(), h.fired.begin(), same))
      Fail("the run's transitions up to event " + std::to_string(p) + " are not the history's");
    return errors_.empty();
  }

  // Value of a domain variable on a stage.
  int Value(const Expr& atom, int stage) const {
    return atom.var_kind == VarKind::kLocation ? t_.locations[atom.target][stage]
                                               : t_.commands[atom.target][stage];
  }

  bool GuardHolds(const Transition& tr, int stage) const {
    return Evaluate(tr.guard, [&](const Expr& atom) { return Value(atom, stage); });
  }

  // Accepting automaton state after event k (0 waiting, 1 active, 2 accepted).
  int EpisodeState(int p, int k) const {
    return (k >= t_.episodes[p].first ? 1 : 0) + (k >= t_.episodes[p].second ? 1 : 0);
  }
  int TemporalState(int q, int k) const {
    int a = std::min(t_.temporals[q].first, t_.temporals[q].second);
    int b = std::max(t_.temporals[q].first, t_.temporals[q].second);
    return (k >= a ? 1 : 0) + (k >= b ? 1 : 0);
  }

  // An accepting automaton read at [i] in a condition of event (or stage) k: its state before k.
  int AcceptingBefore(const Expr& atom, int k) const {
    if (k == 0) return 0;
    return atom.var_kind == VarKind::kEpisodeState ? EpisodeState(atom.target, k - 1)
                                                   : TemporalState(atom.target, k - 1);
  }
  static bool IsAccepting(const Expr& atom) {
    return atom.var_kind == VarKind::kEpisodeState || atom.var_kind == VarKind::kTemporalState;
  }

  // A condition at event k (contract: "When a condition holds").
  bool AtEvent(const Condition& c, int k) const {
    const bool change = c.raw_info.IsChange();
    if (change && k == 0) return false;
    return Evaluate(c.raw, [&](const Expr& atom) {
      if (IsAccepting(atom)) return AcceptingBefore(atom, k);
      int stage = k;
      if (atom.index.kind == IndexKind::kFixed) stage = std::min(atom.index.fixed, g_);
      else if (change && atom.index.kind == IndexKind::kI) stage = k - 1;
      return Value(atom, stage);
    });
  }

  // A state constraint on stage k: [i] and [i+1] both name the stage.
  bool OnStage(const Condition& c, int k) const {
    return Evaluate(c.raw, [&](const Expr& atom) {
      if (IsAccepting(atom)) return AcceptingBefore(atom, k);
      int stage = atom.index.kind == IndexKind::kFixed ? std::min(atom.index.fixed, g_) : k;
      return Value(atom, stage);
    });
  }

  void Dynamics() {
    const std::size_t na = d_.automata.size();
    if (t_.events[0] != 0) Fail("e[0] must be 0");
    for (int k = 1; k <= g_; ++k)
      if (t_.events[k] < t_.events[k - 1]) Fail("event " + std::to_string(k) + " is earlier than the one before");
    for (std::size_t a = 0; a < na; ++a)
      if (t_.locations[a][0] != sp_.initial[a])
        Fail("'" + Name(a) + "' does not start in its initial location");
    // fired[k][a]: transition index firing at event k, or -1.
    std::vector<std::vector<int>> fired(g_ + 1, std::vector<int>(na, -1));
    for (const auto& f : t_.fired) {
      if (f.event < 1 || f.event > g_) {
        Fail("a transition fires outside events 1.." + std::to_string(g_));
        continue;
      }
      if (fired[f.event][f.automaton] >= 0)
        Fail("'" + Name(f.automaton) + "' takes two transitions at event " + std::to_string(f.event));
      fired[f.event][f.automaton] = f.transition;
    }
    std::vector<long> entry(na, 0);
    const int p = t_.history ? t_.history->events() : 0;
    if (t_.history) {
      for (std::size_t a = 0; a < na; ++a) entry[a] = t_.history->entry[a][p];
      for (int k = p + 1; k <= g_; ++k)
        if (t_.events[k] < t_.history->now)
          Fail("event " + std::to_string(k) + " is in the future but earlier than now");
      CheckKeepNext(fired, p);
    }
    for (int k = p + 1; k <= g_; ++k) {
      bool any = false;
      const long now = t_.events[k], before = t_.events[k - 1];
      for (std::size_t a = 0; a < na; ++a) {
        if (Stopped()) return;
        const Automaton& au = d_.automata[a];
        const int loc = t_.locations[a][k - 1];
        const long clock = now - entry[a];
        // Built only when a rule fails: the replay runs on every plan a brute force enumerates.
        auto at = [&] {
          return "'" + au.name + "' at event " + std::to_string(k) + " (t=" + std::to_string(now) +
                 " ticks)";
        };
        const int fi = fired[k][a];
        // Rules over every transition leaving the current location (determinacy, no overstay).
        for (std::size_t ti = 0; ti < au.transitions.size(); ++ti) {
          const Transition& tr = au.transitions[ti];
          if (tr.from != loc || !GuardHolds(tr, k - 1)) continue;
          const long lo = Ticks(tr.duration.lo);
          if (tr.commanded) {
            if (fi != static_cast<int>(ti))
              Fail(at() + ": command '" + au.commands[tr.command > 0 ? tr.command - 1 : 0] +
                   "' was issued but its transition did not fire");
          } else if (tr.controllable || tr.contingent) {
            // The planner (controllable) or nature (contingent) picks the time in [lo, hi].
            if (tr.duration.hi && clock > Ticks(*tr.duration.hi))
              Fail(at() + ": " + (tr.contingent ? "contingent" : "controllable") +
                   " transition overstayed its upper bound");
          } else {
            if (now > std::max(before, entry[a] + lo))
              Fail(at() + ": automatic transition to '" + au.locations[tr.to] +
                   "' was due at clock " + std::to_string(lo) + " but the stage lasted longer");
            if (clock >= lo && fi != static_cast<int>(ti))
              Fail(at() + ": automatic transition to '" + au.locations[tr.to] + "' was enabled but did not fire");
          }
        }
        if (fi < 0) {
          if (t_.locations[a][k] != loc) Fail(at() + ": location changed without a transition");
          continue;
        }
        any = true;
        const Transition& tr = au.transitions[fi];
        if (tr.from != loc || tr.to != t_.locations[a][k])
          Fail(at() + ": the transition does not match the locations before and after");
        if (!GuardHolds(tr, k - 1)) Fail(at() + ": guard '" + tr.guard_text + "' is false on the stage before");
        if (clock < Ticks(tr.duration.lo) || (tr.duration.hi && clock > Ticks(*tr.duration.hi)))
          Fail(at() + ": time in '" + au.locations[loc] + "' is outside the transition's duration");
        entry[a] = now;
      }
      if (!any && !allow_idle_)
        Fail("event " + std::to_string(k) + " carries no transition (runs must be concise)");
    }
  }

  // keep "started": the automaton's first transition after the history is the one named.
  void CheckKeepNext(const std::vector<std::vector<int>>& fired, int p) {
    for (auto [a, ti] : t_.history->keep_next) {
      int first = -1;
      for (int k = p + 1; k <= g_ && first < 0; ++k) first = fired[k][a];
      if (first != ti)
        Fail("'" + Name(a) + "' does not go on with the transition it had started (keep: started)");
    }
  }

  void StatePlanRules() {
    // Episodes.
    for (std::size_t p = 0; p < sp_.episodes.size() && !Stopped(); ++p) {
      const Episode& ep = sp_.episodes[p];
      auto [s, e] = t_.episodes[p];
      const std::string name = "episode '" + ep.name + "'";
      int first = -1;
      for (int k = 0; k <= g_ && first < 0; ++k)
        if (AtEvent(ep.accepting, k)) first = k;
      if (first < 0) {
        Fail(name + ": its accepting constraint never holds");
        continue;
      }
      if (s != first) Fail(name + ": starts at event " + std::to_string(s) + ", not at the first event its accepting constraint holds (" + std::to_string(first) + ")");
      if (!(s < e && e <= g_)) {
        Fail(name + ": must end after it starts and by the goal event");
        continue;
      }
      long dur = t_.events[e] - t_.events[s];
      if (dur < Ticks(ep.lower) || dur > Ticks(ep.upper)) Fail(name + ": lasts outside its bounds");
      for (int k = s; k < e; ++k)
        if (!OnStage(ep.state, k)) Fail(name + ": state constraint fails on stage " + std::to_string(k));
    }
    // Temporal constraints.
    for (std::size_t q = 0; q < sp_.temporals.size() && !Stopped(); ++q) {
      const Temporal& tc = sp_.temporals[q];
      auto [k1, k2] = t_.temporals[q];
      const std::string name = "temporal constraint '" + tc.name + "'";
      if (k1 < 0 || k2 < 0 || k1 > g_ || k2 > g_) {
        Fail(name + ": its events are not accepted by the goal event");
        continue;
      }
      int first = -1;
      for (int k = 0; k <= g_ && first < 0; ++k)
        if (AtEvent(tc.event1, k) || AtEvent(tc.event2, k)) first = k;
      if (first < 0) {
        Fail(name + ": never becomes active");
        continue;
      }
      if (!AtEvent(tc.event1, k1)) Fail(name + ": event 1 does not hold where reported");
      if (!AtEvent(tc.event2, k2)) Fail(name + ": event 2 does not hold where reported");
      if (std::min(k1, k2) != first) Fail(name + ": not activated at the first event either condition holds");
      bool both = AtEvent(tc.event1, first) && AtEvent(tc.event2, first);
      if (both && !(tc.lower == 0 && k1 == k2)) Fail(name + ": both conditions at its first event, but not accepted at once");
      if (!both && k1 == k2) Fail(name + ": accepted at the event that activated it");
      long dt = std::labs(t_.events[k2] - t_.events[k1]);
      if (dt < Ticks(tc.lower) || dt > Ticks(tc.upper)) Fail(name + ": time between its events is outside its bounds");
    }
    if (Stopped()) return;
    ActionRules();
    if (Stopped()) return;
    // Shared events.
    for (const SharedEvent* evp : sp_.AllSharedEvents()) {
      const SharedEvent& ev = *evp;
      std::vector<int> at;
      for (const auto& p : ev.endpoints) {
        switch (p.kind) {
          case EndpointKind::kEpisodeStart: at.push_back(t_.episodes[p.index].first); break;
          case EndpointKind::kEpisodeEnd: at.push_back(t_.episodes[p.index].second); break;
          case EndpointKind::kEvent1: at.push_back(t_.temporals[p.index].first); break;
          case EndpointKind::kEvent2: at.push_back(t_.temporals[p.index].second); break;
          case EndpointKind::kAction:
            at.push_back(OneEvent(p.index));
            if (at.back() < 0)
              Fail("shared event '" + ev.name + "': action '" + sp_.actions[p.index].name + "' never happens");
            break;
          case EndpointKind::kOrder1: at.push_back(t_.orders[p.index].first); break;
          case EndpointKind::kOrder2: at.push_back(t_.orders[p.index].second); break;
        }
      }
      if (std::adjacent_find(at.begin(), at.end(), std::not_equal_to<>()) != at.end())
        Fail("shared event '" + ev.name + "': its endpoints fall on different events");
    }
    if (Stopped()) return;
    // End state: accepted at the first event where the goal holds and all are accepted.
    auto done = [&](int k) {
      if (!AtEvent(sp_.goal, k)) return false;
      for (const auto& [s, e] : t_.episodes)
        if (e > k) return false;
      for (const auto& [a, b] : t_.temporals)
        if (std::max(a, b) > k) return false;
      for (int b : order_accepted_)
        if (b > k) return false;
      return true;
    };
    if (!done(g_)) Fail("the end state is not accepted at the goal event");
    for (int k = 0; k < g_; ++k)
      if (done(k)) {
        Fail("the end state was already accepted at event " + std::to_string(k));
        break;
      }
    for (int k = 0; k < g_; ++k)
      if (!OnStage(sp_.maintenance, k)) Fail("maintenance constraint fails on stage " + std::to_string(k));
  }

  // Action events (contract section 15): the events at which each action fires, its one event
  // (first or last firing, -1 when none), forbidden actions, and the orders' events.
  void ActionRules() {
    firings_.assign(sp_.actions.size(), {});
    for (const auto& f : t_.fired)
      for (std::size_t j = 0; j < sp_.actions.size(); ++j)
        if (sp_.actions[j].Names(f.automaton, f.transition)) firings_[j].push_back(f.event);
    for (auto& v : firings_) std::sort(v.begin(), v.end());
    const int p = t_.history ? t_.history->events() : 0;
    for (int j : sp_.forbidden)
      for (int k : firings_[j])
        if (k > p) Fail("forbidden action '" + sp_.actions[j].name + "' happens at event " + std::to_string(k));
    order_accepted_.assign(sp_.orders.size(), 0);
    for (std::size_t q = 0; q < sp_.orders.size(); ++q) order_accepted_[q] = CheckOrder(q);
  }

  int OneEvent(int j) const {
    const auto& v = firings_[j];
    if (v.empty()) return -1;
    return sp_.actions[j].occurrence == Occurrence::kLast ? v.back() : v.front();
  }

  int FirstHolding(const Condition& c, int from, bool lower_passed_from_ref, int ref, long lower) const {
    for (int k = std::max(from, 0); k <= g_; ++k)
      if (AtEvent(c, k) && (!lower_passed_from_ref || t_.events[k] - t_.events[ref] >= lower)) return k;
    return -1;
  }

  // Checks order q; returns the event at which it is accepted (beyond g when it is not).
  int CheckOrder(std::size_t q) {
    const Order& o = sp_.orders[q];
    const std::string name = o.name.empty() ? "sequence step " + o.pointer : "temporal constraint '" + o.name + "'";
    const int never = g_ + 1;
    const long lower = Ticks(o.lower);
    auto within = [&](long dt) { return dt >= lower && (!o.upper || dt <= Ticks(*o.upper)); };
    auto action_event = [&](const OrderEnd& e) {
      int k = OneEvent(e.action);
      if (k < 0) Fail(name + ": action '" + sp_.actions[e.action].name + "' never happens");
      return k;
    };
    auto every = [&](const OrderEnd& e) {
      return e.action >= 0 && sp_.actions[e.action].occurrence == Occurrence::kEvery;
    };
    int e1 = -1, e2 = -1;
    if (o.ordered) {
      e1 = o.first.action >= 0 ? action_event(o.first) : FirstHolding(o.first.condition, 0, false, 0, 0);
      if (e1 < 0) {
        if (o.first.action < 0) Fail(name + ": its first event's condition never holds");
        return never;
      }
      const int from = o.strict ? e1 + 1 : e1;
      if (every(o.second)) {
        e2 = e1;
        for (int k : firings_[o.second.action]) {
          if (k < from) Fail(name + ": '" + sp_.actions[o.second.action].name + "' happens at event " +
                             std::to_string(k) + ", before its first event");
          else if (!within(t_.events[k] - t_.events[e1]))
            Fail(name + ": '" + sp_.actions[o.second.action].name + "' at event " + std::to_string(k) +
                 " is outside its bounds");
          e2 = std::max(e2, k);
        }
      } else {
        e2 = o.second.action >= 0 ? action_event(o.second)
                                  : FirstHolding(o.second.condition, from, true, e1, lower);
        if (e2 < 0) {
          if (o.second.action < 0) Fail(name + ": its second event's condition does not hold after the first in time");
          return never;
        }
        if (e2 < from) Fail(name + ": its second event (" + std::to_string(e2) + ") is not after its first (" + std::to_string(e1) + ")");
        else if (!within(t_.events[e2] - t_.events[e1])) Fail(name + ": time between its events is outside its bounds");
      }
    } else {
      const bool first_is_action = o.first.action >= 0;
      const OrderEnd& act = first_is_action ? o.first : o.second;
      const OrderEnd& other = first_is_action ? o.second : o.first;
      const int x = action_event(act);
      if (x < 0) return never;
      int y = -1;
      if (other.action >= 0) {
        y = action_event(other);
      } else {
        y = FirstHolding(other.condition, 0, false, 0, 0);
        if (y < 0 || y > x) y = FirstHolding(other.condition, x + 1, true, x, lower);
        if (y < 0) Fail(name + ": its condition does not hold in time");
      }
      if (y < 0) return never;
      (first_is_action ? e1 : e2) = x;
      (first_is_action ? e2 : e1) = y;
      if (!within(std::labs(t_.events[e2] - t_.events[e1]))) Fail(name + ": time between its events is outside its bounds");
    }
    if (t_.orders[q] != std::make_pair(e1, e2))
      Fail(name + ": reported at events (" + std::to_string(t_.orders[q].first) + ", " +
           std::to_string(t_.orders[q].second) + "), but its events are (" + std::to_string(e1) + ", " +
           std::to_string(e2) + ")");
    return every(o.second) ? e1 : std::max(e1, e2);
  }

  const Trajectory& t_;
  const Domain& d_;
  const StatePlan& sp_;
  long tps_;
  int g_;
  std::vector<std::string> errors_;
  std::vector<std::vector<int>> firings_;  // per action: the events it fires at, ascending
  std::vector<int> order_accepted_;        // per order: the event it is accepted at
};

}  // namespace

std::vector<std::string> VerifyTrajectory(const Trajectory& t, const Domain& d,
                                          const StatePlan& sp, long ticks_per_second,
                                          bool allow_idle_events) {
  Replay r(t, d, sp, ticks_per_second);
  r.allow_idle_ = allow_idle_events;
  return r.Run();
}

bool TrajectoryIsPlan(const Trajectory& t, const Domain& d, const StatePlan& sp,
                      long ticks_per_second) {
  Replay r(t, d, sp, ticks_per_second);
  r.stop_at_first_ = true;
  return r.Run().empty();
}

}  // namespace ctb
