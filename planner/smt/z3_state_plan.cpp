// The state plan's accepting automata as z3 terms: the counterpart of
// planner/encode/encode_state_plan.cpp (episodes, temporal constraints, shared events, the end
// state and the maintenance constraint). Event indices are in order encoding (OrderVar); an
// array read at a variable index (ACC[EP_S], e[EP_E], ...) becomes one implication per index.
#include <cmath>
#include <string>

#include "planner/smt/z3_model.h"

namespace ctb::smt {

namespace {

// Adds the constraints made in its scope under `lit` (nothing when the parts are not switched).
class Gate {
 public:
  Gate(Model& m, const z3::expr* lit) : m_(m) {
    if (lit) m_.gate = *lit;
  }
  ~Gate() { m_.gate.reset(); }

 private:
  Model& m_;
};

const z3::expr* Literal(const Model& m, const Exprs PartLiterals::*group, int i) {
  return m.parts ? &((*m.parts).*group)[i] : nullptr;
}

long Ticks(const Model& m, double seconds) {
  return std::lround(seconds * static_cast<double>(m.info.ticks_per_second));
}

Exprs CondArray(Model& m, const Condition& c, CondMode mode) {
  Exprs out;
  for (int k = 0; k <= m.H; ++k) out.push_back(CondAt(m, c.expr, c.info, mode, k));
  return out;
}

// idx is the first index at which cond holds: cond[idx] and not cond[k] for every k < idx.
void FirstHolds(Model& m, const OrderVar& idx, const Exprs& cond) {
  for (int k = 0; k <= m.H; ++k) {
    m.Add(z3::implies(idx.Eq(k), cond[k]));
    m.Add(z3::implies(idx.Gt(k), !cond[k]));
  }
}

// a < b.
void Less(Model& m, const OrderVar& a, const OrderVar& b) {
  for (int k = 0; k <= m.H; ++k) m.Add(z3::implies(a.Eq(k), b.Gt(k)));
}

// a <= b.
void AtMost(Model& m, const OrderVar& a, const OrderVar& b) {
  for (int k = 0; k < m.H; ++k) m.Add(z3::implies(a.Gt(k), b.Gt(k)));
}

z3::expr Equal(Model& m, const OrderVar& a, const OrderVar& b) {
  z3::expr eq = m.True();
  for (int k = 0; k < m.H; ++k) eq = eq && a.gt[k] == b.gt[k];
  return eq;
}

// lo <= e[to] - e[from] <= hi.
void TimeBetween(Model& m, const OrderVar& from, const OrderVar& to, double lo, double hi,
                 const std::string& name) {
  z3::expr t0 = m.At(m.e, from, name + "_t0"), t1 = m.At(m.e, to, name + "_t1");
  m.Add(t1 - t0 >= m.Val(Ticks(m, lo)) && t1 - t0 <= m.Val(Ticks(m, hi)));
}

// Episode p: starts at the first event at which its accepting condition holds, ends at a later
// event no later than g, lasts within its bounds; its state constraint holds from start to end.
void AddEpisode(Model& m, int p) {
  Gate gate(m, Literal(m, &PartLiterals::episodes, p));
  const Episode& ep = m.sp.episodes[p];
  const OrderVar &s = m.ep_s[p], &e = m.ep_e[p];
  FirstHolds(m, s, CondArray(m, ep.accepting, CondMode::kEvent));
  Less(m, s, e);
  AtMost(m, e, m.g);
  TimeBetween(m, s, e, ep.lower, ep.upper, "EP_" + std::to_string(p));
  if (IsTrueCondition(ep.state)) return;
  for (int k = 0; k <= m.H; ++k)
    m.Add(z3::implies(s.Le(k) && e.Gt(k),
                      CondAt(m, ep.state.expr, ep.state.info, CondMode::kStage, k)));
}

// Temporal constraint q: active at the first event at which either condition holds (TC_A),
// accepted at the other (TC_B) no later than g, the time between within bounds; both at the
// first event: accepted at once when the lower bound is 0, failed otherwise.
void AddTemporal(Model& m, int q) {
  Gate gate(m, Literal(m, &PartLiterals::temporals, q));
  const Temporal& tc = m.sp.temporals[q];
  const OrderVar &t1 = m.tc_1[q], &t2 = m.tc_2[q], &ta = m.tc_a[q], &tb = m.tc_b[q];
  Exprs c1 = CondArray(m, tc.event1, CondMode::kEvent);
  Exprs c2 = CondArray(m, tc.event2, CondMode::kEvent);
  z3::expr both = m.Bool("TC_BOTH_" + std::to_string(q));
  for (int k = 0; k < m.H; ++k) {  // TC_A = min(TC_1, TC_2), TC_B = max(TC_1, TC_2)
    m.Add(ta.gt[k] == (t1.gt[k] && t2.gt[k]));
    m.Add(tb.gt[k] == (t1.gt[k] || t2.gt[k]));
  }
  for (int k = 0; k <= m.H; ++k) {
    m.Add(z3::implies(t1.Eq(k), c1[k]));
    m.Add(z3::implies(t2.Eq(k), c2[k]));
    m.Add(z3::implies(ta.Gt(k), !(c1[k] || c2[k])));
    m.Add(z3::implies(ta.Eq(k), both == (c1[k] && c2[k])));
  }
  if (tc.lower > 0)
    m.Add(!both);
  else
    m.Add(both == Equal(m, t1, t2));
  AtMost(m, tb, m.g);
  TimeBetween(m, ta, tb, tc.lower, tc.upper, "TC_" + std::to_string(q));
}

// Shared events: every endpoint of one entry falls on the same event.
void AddSharedEvents(Model& m) {
  auto var = [&](const Endpoint& p) -> const OrderVar& {
    switch (p.kind) {
      case EndpointKind::kEpisodeStart: return m.ep_s[p.index];
      case EndpointKind::kEpisodeEnd: return m.ep_e[p.index];
      case EndpointKind::kEvent1: return m.tc_1[p.index];
      case EndpointKind::kEvent2: break;
    }
    return m.tc_2[p.index];
  };
  if (!m.parts) {
    for (const auto& ev : m.sp.events)
      for (std::size_t k = 1; k < ev.endpoints.size(); ++k)
        m.Add(Equal(m, var(ev.endpoints[0]), var(ev.endpoints[k])));
    return;
  }
  // Switched: the endpoints of the parts still there are pairwise equal.
  auto owner = [&](const Endpoint& p) {
    const bool episode =
        p.kind == EndpointKind::kEpisodeStart || p.kind == EndpointKind::kEpisodeEnd;
    return episode ? m.parts->episodes[p.index] : m.parts->temporals[p.index];
  };
  for (std::size_t v = 0; v < m.sp.events.size(); ++v) {
    const auto& ends = m.sp.events[v].endpoints;
    for (std::size_t i = 0; i < ends.size(); ++i)
      for (std::size_t j = i + 1; j < ends.size(); ++j)
        m.Add(z3::implies(m.parts->events[v] && owner(ends[i]) && owner(ends[j]),
                          Equal(m, var(ends[i]), var(ends[j]))));
  }
}

// g is the first event at which the goal holds and every episode and temporal constraint is
// accepted; the maintenance constraint holds on every stage before it.
void AddEndState(Model& m) {
  Exprs done = CondArray(m, m.sp.goal, CondMode::kEvent);
  const PartLiterals* lit = m.parts ? &*m.parts : nullptr;
  for (int k = 0; k <= m.H; ++k) {
    if (lit) done[k] = z3::implies(lit->goal, done[k]);
    for (std::size_t p = 0; p < m.ep_e.size(); ++p)
      done[k] = done[k] && (lit ? z3::implies(lit->episodes[p], m.ep_e[p].Le(k)) : m.ep_e[p].Le(k));
    for (std::size_t q = 0; q < m.tc_b.size(); ++q)
      done[k] =
          done[k] && (lit ? z3::implies(lit->temporals[q], m.tc_b[q].Le(k)) : m.tc_b[q].Le(k));
  }
  FirstHolds(m, m.g, done);
  if (IsTrueCondition(m.sp.maintenance)) return;
  Gate gate(m, lit ? &lit->maintenance : nullptr);
  for (int k = 0; k <= m.H; ++k)
    m.Add(z3::implies(m.g.Gt(k), CondAt(m, m.sp.maintenance.expr, m.sp.maintenance.info,
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
