// The state plan's accepting automata as z3 terms: the counterpart of
// planner/encode/encode_state_plan.cpp (episodes, temporal constraints, shared events, the end
// state and the maintenance constraint). An array read at a variable index (ACC[EP_S],
// e[EP_E], ...) is unfolded into one implication per index value.
#include <cmath>
#include <string>

#include "planner/smt/z3_model.h"

namespace ctb::smt {

namespace {

long Ticks(const Model& m, double seconds) {
  return std::lround(seconds * static_cast<double>(m.info.ticks_per_second));
}

Exprs CondArray(Model& m, const Condition& c, CondMode mode) {
  Exprs out;
  for (int k = 0; k <= m.H; ++k) out.push_back(CondAt(m, c.expr, c.info, mode, k));
  return out;
}

// idx is the first index at which cond holds: cond[idx] and not cond[k] for every k < idx.
void FirstHolds(Model& m, const z3::expr& idx, const Exprs& cond) {
  for (int k = 0; k <= m.H; ++k) {
    m.Add(z3::implies(idx == k, cond[k]));
    m.Add(z3::implies(idx > k, !cond[k]));
  }
}

// lo <= e[to] - e[from] <= hi.
void TimeBetween(Model& m, const z3::expr& from, const z3::expr& to, double lo, double hi,
                 const std::string& name) {
  z3::expr t0 = m.At(m.e, from, name + "_t0"), t1 = m.At(m.e, to, name + "_t1");
  m.Add(t1 - t0 >= m.Val(Ticks(m, lo)) && t1 - t0 <= m.Val(Ticks(m, hi)));
}

void Range(Model& m, const z3::expr& v) { m.Add(v >= 0 && v <= m.H); }

// Episode p: starts at the first event at which its accepting condition holds, ends at a later
// event no later than g, lasts within its bounds; its state constraint holds from start to end.
void AddEpisode(Model& m, int p) {
  const Episode& ep = m.sp.episodes[p];
  const z3::expr &s = m.ep_s[p], &e = m.ep_e[p];
  Range(m, s);
  Range(m, e);
  FirstHolds(m, s, CondArray(m, ep.accepting, CondMode::kEvent));
  m.Add(s < e && e <= m.g);
  TimeBetween(m, s, e, ep.lower, ep.upper, "EP_" + std::to_string(p));
  if (IsTrueCondition(ep.state)) return;
  for (int k = 0; k <= m.H; ++k)
    m.Add(z3::implies(s <= k && e > k, CondAt(m, ep.state.expr, ep.state.info,
                                                 CondMode::kStage, k)));
}

// Temporal constraint q: active at the first event at which either condition holds (TC_A),
// accepted at the other (TC_B) no later than g, the time between within bounds; both at the
// first event: accepted at once when the lower bound is 0, failed otherwise.
void AddTemporal(Model& m, int q) {
  const Temporal& tc = m.sp.temporals[q];
  const z3::expr &t1 = m.tc_1[q], &t2 = m.tc_2[q], &ta = m.tc_a[q], &tb = m.tc_b[q];
  for (const z3::expr* v : {&t1, &t2, &ta, &tb}) Range(m, *v);
  Exprs c1 = CondArray(m, tc.event1, CondMode::kEvent);
  Exprs c2 = CondArray(m, tc.event2, CondMode::kEvent);
  z3::expr both = m.z.bool_const(("TC_BOTH_" + std::to_string(q)).c_str());
  ++m.declared;
  for (int k = 0; k <= m.H; ++k) {
    m.Add(z3::implies(t1 == k, c1[k]));
    m.Add(z3::implies(t2 == k, c2[k]));
    m.Add(z3::implies(ta > k, !(c1[k] || c2[k])));
    m.Add(z3::implies(ta == k, both == (c1[k] && c2[k])));
  }
  m.Add(ta == z3::ite(t1 <= t2, t1, t2) && tb == z3::ite(t1 <= t2, t2, t1));
  if (tc.lower > 0)
    m.Add(!both);
  else
    m.Add(both == (t1 == t2));
  m.Add(tb <= m.g);
  TimeBetween(m, ta, tb, tc.lower, tc.upper, "TC_" + std::to_string(q));
}

// Shared events: every endpoint of one entry falls on the same event.
void AddSharedEvents(Model& m) {
  auto var = [&](const Endpoint& p) -> z3::expr {
    switch (p.kind) {
      case EndpointKind::kEpisodeStart: return m.ep_s[p.index];
      case EndpointKind::kEpisodeEnd: return m.ep_e[p.index];
      case EndpointKind::kEvent1: return m.tc_1[p.index];
      case EndpointKind::kEvent2: return m.tc_2[p.index];
    }
    return m.z.int_val(0);
  };
  for (const auto& ev : m.sp.events)
    for (std::size_t k = 1; k < ev.endpoints.size(); ++k)
      m.Add(var(ev.endpoints[0]) == var(ev.endpoints[k]));
}

// g is the first event at which the goal holds and every episode and temporal constraint is
// accepted; the maintenance constraint holds on every stage before it.
void AddEndState(Model& m) {
  Exprs done = CondArray(m, m.sp.goal, CondMode::kEvent);
  for (int k = 0; k <= m.H; ++k) {
    for (const auto& e : m.ep_e) done[k] = done[k] && e <= k;
    for (const auto& b : m.tc_b) done[k] = done[k] && b <= k;
  }
  FirstHolds(m, m.g, done);
  if (IsTrueCondition(m.sp.maintenance)) return;
  for (int k = 0; k <= m.H; ++k)
    m.Add(z3::implies(m.g > k, CondAt(m, m.sp.maintenance.expr, m.sp.maintenance.info,
                                         CondMode::kStage, k)));
}

}  // namespace

void AddStatePlan(Model& m) {
  for (int p = 0; p < static_cast<int>(m.sp.episodes.size()); ++p) AddEpisode(m, p);
  for (int q = 0; q < static_cast<int>(m.sp.temporals.size()); ++q) AddTemporal(m, q);
  AddSharedEvents(m);
  AddEndState(m);
}

}  // namespace ctb::smt
