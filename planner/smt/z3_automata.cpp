// The action model as z3 terms: the counterpart of planner/encode/encode_automata.cpp, one
// function per emitter there, with the same constraints (MiniZinc's TAB, LO/HI, CMD and FROM
// arrays are unfolded per transition; L, X and U are one-hot Booleans).
#include <algorithm>

#include "planner/expr/normalize.h"
#include "planner/smt/z3_model.h"

namespace ctb::smt {

namespace {

z3::expr Guard(Model& m, const Transition& t, int k) {
  return CondAt(m, t.guard, ExprInfo{}, CondMode::kGuard, k);
}

// "L[a,k] = FROM /\ G(k)": transition t of automaton a is enabled on stage k.
z3::expr Enabled(Model& m, int a, const Transition& t, int k) {
  z3::expr s = m.LocIs(a, k, t.from);
  if (!IsTrue(t.guard)) s = s && Guard(m, t, k);
  return s;
}

long Hi(const Model& m, int id) { return m.info.hi[id] < 0 ? m.T : std::min(m.info.hi[id], m.T); }

// Events are ordered in time; e[0] = 0; every time lies in 0..T.
void AddEvents(Model& m) {
  m.Add(m.e[0] == 0);
  for (int k = 0; k <= m.H; ++k) m.Add(m.e[k] >= 0 && m.e[k] <= m.Val(m.T));
  for (int k = 0; k < m.H; ++k) m.Add(m.e[k] <= m.e[k + 1]);
}

// One location per stage; (L[a,k], X[a,k], L[a,k+1]) is a stay or one transition (the rows of
// MiniZinc's TAB); entry times follow; the clock at the firing event lies in the transition's
// [LO, HI] (no transition: [0, T]).
void AddLocationUpdate(Model& m, int a) {
  const Automaton& au = m.d.automata[a];
  const auto& ids = m.info.transitions_of[a];
  const int nl = static_cast<int>(au.locations.size());
  m.Add(m.LocIs(a, 0, m.sp.initial[a]));
  m.Add(m.N[a][0] == 0);
  for (int k = 0; k <= m.H; ++k) {
    m.One(m.loc[a][k], true);
    m.Add(m.N[a][k] >= 0 && m.N[a][k] <= m.Val(m.T));
    if (m.opts.redundant) m.Add(m.N[a][k] <= m.e[k]);
  }
  for (int k = 0; k < m.H; ++k) {
    const z3::expr clock = m.e[k + 1] - m.N[a][k];
    const z3::expr& none = m.idle[a][k];
    m.One(m.fire[a][k], false);
    z3::expr stay = m.N[a][k + 1] == m.N[a][k];
    for (int l = 0; l < nl; ++l) stay = stay && m.LocIs(a, k + 1, l) == m.LocIs(a, k, l);
    m.Add(z3::implies(none, stay));
    m.Add(z3::implies(!none, m.N[a][k + 1] == m.e[k + 1]));
    m.Add(clock >= 0 && clock <= m.Val(m.T));
    for (std::size_t i = 0; i < ids.size(); ++i) {
      const Transition& t = au.transitions[i];
      const int id = ids[i];
      m.Add(z3::implies(m.fire[a][k][i], m.LocIs(a, k, t.from) && m.LocIs(a, k + 1, t.to) &&
                                             clock >= m.Val(m.info.lo[id]) &&
                                             clock <= m.Val(Hi(m, id))));
    }
  }
}

// A transition fires only when its guard holds on the stage before the event.
void AddGuards(Model& m, int a) {
  const Automaton& au = m.d.automata[a];
  for (std::size_t i = 0; i < au.transitions.size(); ++i) {
    const Transition& t = au.transitions[i];
    if (IsTrue(t.guard)) continue;
    for (int k = 0; k < m.H; ++k) m.Add(z3::implies(m.fire[a][k][i], Guard(m, t, k)));
  }
}

// Commands: private ones are the command the firing transition requires (the no-op for none);
// public ones are free, and a commanded transition whose guard holds must fire.
void AddCommands(Model& m, int a) {
  const Automaton& au = m.d.automata[a];
  const int nc = static_cast<int>(au.commands.size());
  for (int k = 0; k <= m.H; ++k) m.One(m.cmd[a][k], true);
  m.Add(m.CmdIs(a, m.H, 0));
  for (int k = 0; k < m.H; ++k) {
    if (!m.info.command_public[a]) {
      // U[a,k] = CMD[X[a,k]]: command c exactly when a transition requiring c fires.
      for (int c = 1; c <= nc; ++c) {
        z3::expr_vector causes(m.z);
        for (std::size_t i = 0; i < au.transitions.size(); ++i) {
          const Transition& t = au.transitions[i];
          if (t.commanded && t.command == c) causes.push_back(m.fire[a][k][i]);
        }
        m.Add(m.CmdIs(a, k, c) == (causes.empty() ? m.False() : z3::mk_or(causes)));
      }
      continue;
    }
    for (std::size_t i = 0; i < au.transitions.size(); ++i) {
      const Transition& t = au.transitions[i];
      if (t.commanded) m.Add(z3::implies(Enabled(m, a, t, k), m.fire[a][k][i]));
    }
  }
}

// Automatic transitions fire as soon as enabled (no later than max(e[k], N + lo)); controllable
// ones no later than hi; nothing is forced at or after g.
void AddAutomatic(Model& m, int a) {
  const Automaton& au = m.d.automata[a];
  for (std::size_t i = 0; i < au.transitions.size(); ++i) {
    const Transition& t = au.transitions[i];
    if (t.commanded) continue;
    const int id = m.info.transitions_of[a][i];
    const long lo = m.info.lo[id];
    if (t.controllable && m.info.hi[id] < 0) continue;
    for (int k = 0; k < m.H; ++k) {
      const z3::expr& fire = m.fire[a][k][i];
      z3::expr then = m.True();
      if (t.controllable) {
        then = m.e[k + 1] - m.N[a][k] <= m.Val(m.info.hi[id]);
      } else if (lo == 0) {
        then = m.e[k + 1] == m.e[k] && fire;
      } else {
        z3::expr due = m.N[a][k] + m.Val(lo);
        then = (m.e[k + 1] <= m.e[k] || m.e[k + 1] <= due) && z3::implies(m.e[k + 1] >= due, fire);
      }
      m.Add(z3::implies(m.g.Gt(k) && Enabled(m, a, t, k), then));
    }
  }
}

// Concise runs: every event up to g carries a transition (relaxed: events after g carry none);
// padding events keep e[g]'s time.
void AddConcise(Model& m) {
  for (int k = 0; k < m.H; ++k) {
    z3::expr_vector fired(m.z);
    for (std::size_t a = 0; a < m.d.automata.size(); ++a) fired.push_back(!m.idle[a][k]);
    z3::expr any = fired.empty() ? m.False() : z3::mk_or(fired);
    if (m.opts.idle_events)
      m.Add(z3::implies(any, m.g.Gt(k)));
    else
      m.Add(m.g.Gt(k) == any);
    m.Add(z3::implies(m.g.Le(k), m.e[k + 1] == m.e[k]));
  }
}

}  // namespace

void AddAutomata(Model& m) {
  AddEvents(m);
  for (int a = 0; a < static_cast<int>(m.d.automata.size()); ++a) {
    AddLocationUpdate(m, a);
    AddGuards(m, a);
    AddCommands(m, a);
    AddAutomatic(m, a);
  }
  AddConcise(m);
}

}  // namespace ctb::smt
