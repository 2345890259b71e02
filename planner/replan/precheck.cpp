#include "planner/replan/precheck.h"

#include <algorithm>
#include <cmath>

#include "planner/analyze/analyze.h"
#include "planner/expr/expr_print.h"

namespace ctb::replan {

namespace {

std::string Secs(long ticks, long tps) {
  if (tps == 1) return std::to_string(ticks);
  return Json(static_cast<double>(ticks) / static_cast<double>(tps)).dump();
}
Json SecsJson(long ticks, long tps) {
  if (tps == 1) return ticks;
  return static_cast<double>(ticks) / static_cast<double>(tps);
}
long Ticks(double seconds, long tps) { return std::lround(seconds * static_cast<double>(tps)); }

// Only conditions over locations at [i]/[i+1] are evaluated on the history.
bool Evaluable(const Condition& c) {
  const ExprInfo& i = c.raw_info;
  return !i.uses_fixed && i.commands_read.empty() && i.episodes_read.empty() &&
         i.temporals_read.empty();
}

class HistoryView {
 public:
  explicit HistoryView(const History& h) : h_(h), p_(h.events()) {}
  int p() const { return p_; }
  long time(int k) const { return h_.times[k]; }

  // A condition at event k (contract: "When a condition holds"); Evaluable conditions only.
  bool AtEvent(const Condition& c, int k) const {
    const bool change = c.raw_info.IsChange();
    if (change && k == 0) return false;
    return Evaluate(c.raw, [&](const Expr& atom) {
      int stage = change && atom.index.kind == IndexKind::kI ? k - 1 : k;
      return h_.locations[atom.target][stage];
    });
  }
  bool OnStage(const Condition& c, int k) const {
    return Evaluate(c.raw, [&](const Expr& atom) { return h_.locations[atom.target][k]; });
  }

 private:
  const History& h_;
  int p_;
};

std::string PartPointer(const Condition& c) { return c.pointer.substr(0, c.pointer.rfind('/')); }

Json Conflict(const std::string& pointer, const std::string& text, long at, long tps) {
  return {{"constraints", {pointer}}, {"text", text}, {"broken_at", SecsJson(at, tps)}};
}

}  // namespace

std::vector<Json> BrokenByHistory(const StatePlan& sp, const Situation& s) {
  std::vector<Json> out;
  const HistoryView h(s.history);
  const int p = h.p();
  const long now = s.history.now, tps = s.tps;
  for (const Temporal& tc : sp.temporals) {
    if (!Evaluable(tc.event1) || !Evaluable(tc.event2)) continue;
    int first = -1;
    for (int k = 0; k <= p && first < 0; ++k)
      if (h.AtEvent(tc.event1, k) || h.AtEvent(tc.event2, k)) first = k;
    if (first < 0) continue;
    const std::string ptr = PartPointer(tc.event1), name = "temporal constraint '" + tc.name + "'";
    const bool c1 = h.AtEvent(tc.event1, first), c2 = h.AtEvent(tc.event2, first);
    if (c1 && c2) {
      if (tc.lower > 0)
        out.push_back(Conflict(ptr, name + " was broken at t = " + Secs(h.time(first), tps) +
                                        " s: both its events happened at once, and its lower bound is " +
                                        Secs(Ticks(tc.lower, tps), tps) + " s",
                               h.time(first), tps));
      continue;
    }
    const Condition& other = c1 ? tc.event2 : tc.event1;
    const long lo = Ticks(tc.lower, tps), up = Ticks(tc.upper, tps), t0 = h.time(first);
    bool done = false;
    for (int k = first + 1; k <= p && !done; ++k)
      done = h.AtEvent(other, k) && h.time(k) - t0 >= lo && h.time(k) - t0 <= up;
    if (done || now - t0 <= up) continue;
    out.push_back(Conflict(ptr, name + " was broken at t = " + Secs(t0 + up, tps) + " s: its " +
                                    (c1 ? "first" : "second") + " event happened at t = " +
                                    Secs(t0, tps) + " s and its " + (c1 ? "second" : "first") +
                                    " had not come by its upper bound of " + Secs(up, tps) +
                                    " s after it (now is " + Secs(now, tps) + " s)",
                           t0 + up, tps));
  }
  for (const Episode& ep : sp.episodes) {
    if (!Evaluable(ep.accepting) || !Evaluable(ep.state)) continue;
    int first = -1;
    for (int k = 0; k <= p && first < 0; ++k)
      if (h.AtEvent(ep.accepting, k)) first = k;
    if (first < 0) continue;
    const long lo = Ticks(ep.lower, tps), up = Ticks(ep.upper, tps), t0 = h.time(first);
    int fail = -1;
    bool done = false;
    for (int k = first; k <= p && fail < 0 && !done; ++k) {
      if (k > first && h.time(k) - t0 >= lo && h.time(k) - t0 <= up) done = true;  // may end at k
      else if (!h.OnStage(ep.state, k)) fail = k;
    }
    const std::string ptr = PartPointer(ep.accepting), name = "episode '" + ep.name + "'";
    if (done) continue;
    if (fail >= 0) {
      out.push_back(Conflict(ptr, name + " was broken at t = " + Secs(h.time(fail), tps) +
                                      " s: it started at t = " + Secs(t0, tps) +
                                      " s and its state constraint stopped holding " +
                                      "before it could last its lower bound of " + Secs(lo, tps) + " s",
                             h.time(fail), tps));
    } else if (now - t0 > up) {
      out.push_back(Conflict(ptr, name + " was broken at t = " + Secs(t0 + up, tps) +
                                      " s: it started at t = " + Secs(t0, tps) +
                                      " s and had not ended by its upper bound of " + Secs(up, tps) +
                                      " s (now is " + Secs(now, tps) + " s)",
                             t0 + up, tps));
    }
  }
  if (Evaluable(sp.maintenance))
    for (int k = 0; k < p; ++k)
      if (!h.OnStage(sp.maintenance, k)) {
        out.push_back(Conflict(sp.maintenance.pointer, "the maintenance constraint was broken at t = " +
                                                           Secs(h.time(k), tps) + " s",
                               h.time(k), tps));
        break;
      }
  return out;
}

namespace {

// The remaining problem from the state at now: the goal alone (and the parts not yet begun when
// none has begun). nullopt when it cannot be stated apart (the goal reads more than locations).
std::optional<StatePlan> Remaining(const StatePlan& sp, const Situation& s, bool goal_only) {
  if (!Evaluable(sp.goal)) return std::nullopt;
  StatePlan r = sp;
  const int p = s.history.events();
  for (std::size_t a = 0; a < r.initial.size(); ++a) r.initial[a] = s.history.locations[a][p];
  bool begun = false;
  const HistoryView h(s.history);
  for (const auto& ep : sp.episodes)
    for (int k = 0; k <= p && !begun; ++k) begun = !Evaluable(ep.accepting) || h.AtEvent(ep.accepting, k);
  for (const auto& tc : sp.temporals)
    for (int k = 0; k <= p && !begun; ++k)
      begun = !Evaluable(tc.event1) || !Evaluable(tc.event2) || h.AtEvent(tc.event1, k) ||
              h.AtEvent(tc.event2, k);
  if (goal_only || begun) {
    r.episodes.clear();
    r.temporals.clear();
    r.events.clear();
    r.maintenance.expr = Expr{};
    r.maintenance.raw = Expr{};
    r.maintenance.info = ExprInfo{};
    r.maintenance.raw_info = ExprInfo{};
    r.maintenance.text = "true";
  } else {
    // Parts not begun are evaluated afresh from the state at now; every condition must then be
    // one the remaining problem can read the same way.
    auto ok = [](const Condition& c) { return Evaluable(c); };
    for (const auto& ep : sp.episodes)
      if (!ok(ep.accepting) || !ok(ep.state)) return Remaining(sp, s, true);
    if (!ok(sp.maintenance)) return Remaining(sp, s, true);
  }
  return r;
}

}  // namespace

std::optional<Json> GoalCutOff(const Domain& d, const StatePlan& sp, const Situation& s) {
  auto r = Remaining(sp, s, true);
  if (!r) return std::nullopt;
  auto conflict = [&](const Domain& dom) {
    for (const auto& c : FindStaticConflicts(dom, *r))
      if (std::find(c.parts.begin(), c.parts.end(), sp.goal.pointer) != c.parts.end()) return true;
    return false;
  };
  if (!conflict(s.analysis_domain)) return std::nullopt;
  Json pointers = {sp.goal.pointer};
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
  return Json{{"constraints", pointers}, {"text", text}};
}

ObjectiveBounds HistoryBounds(const StatePlan& sp, const Situation& s) {
  const History& h = s.history;
  const int p = h.events();
  ObjectiveBounds b;
  b.cost = s.history_cost;
  b.makespan_ticks = h.times[p];
  b.events = p;
  auto r = Remaining(sp, s, false);
  if (!r) return b;
  const ObjectiveBounds rest = LowerBounds(s.analysis_domain, *r);
  // The time origin of the remaining problem: no transition from a location held at now fires
  // before max(its entry + lo, now), so none fires before `since + lo` (docs/replanning.md).
  long since = h.now;
  for (std::size_t a = 0; a < h.entry.size(); ++a)
    for (const Transition& t : s.analysis_domain.automata[a].transitions)
      if (t.from == h.locations[a][p])
        since = std::min(since, std::max(h.entry[a][p], h.now - Ticks(t.duration.lo, s.tps)));
  b.cost += rest.cost;
  b.events += rest.events;
  b.makespan_ticks = std::max(b.makespan_ticks, since + rest.makespan_ticks);
  if (rest.events > 0) b.makespan_ticks = std::max(b.makespan_ticks, h.now);
  return b;
}

}  // namespace ctb::replan
