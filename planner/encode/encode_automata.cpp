// Emitters for the action model: transition choice and location update, entry times and
// durations, guards, commands, automatic and controllable transitions, concise runs.
#include <string>

#include "planner/encode/emit.h"

namespace ctb::encode {

namespace {


ExprInfo GuardInfo() { return ExprInfo{}; }  // guards read [i] only: stage mode prints k

// "L[a,k] = FROM /\ G(k)" for transition t of automaton a (1-based a in the text).
std::string Enabled(const Context& c, int a, const Transition& t) {
  std::string s = "L[" + std::to_string(a + 1) + ",k] = " + std::to_string(t.from);
  if (!IsTrue(t.guard)) s += " /\\ " + PrintCondition(c, t.guard, GuardInfo(), CondMode::kGuard);
  return s;
}

}  // namespace

// Events are ordered in time; e[0] = 0.
void EmitEvents(const Context& c) {
  c.out += "% events\nconstraint e[0] = 0;\n";
  c.out += "constraint forall(k in 0..H-1)(e[k] <= e[k+1]);\n";
}

// Location update: (L[a,k], X[a,k], L[a,k+1]) is a row of TAB (stay, or one transition);
// entry times follow; the clock at the firing event lies in the transition's duration window.
void EmitLocationUpdate(const Context& c) {
  std::string& o = c.out;
  o += "% locations, transitions, entry times, durations\n";
  o += "constraint forall(a in 1..NA)(L[a,0] = INIT[a] /\\ N[a,0] = 0);\n";
  o += "constraint forall(a in 1..NA, k in 0..H)(L[a,k] < NLOC[a]);\n";
  o += "constraint forall(a in 1..NA, k in 0..H-1)(X[a,k] in TRS[a]);\n";
  // After a fixed history (replanning) these rules apply from event P on.
  const std::string rng = "forall(a in 1..NA, k in " + c.K0() + "..H-1)";
  o += "constraint " + rng + "(table([a, L[a,k], X[a,k], L[a,k+1]], TAB));\n";
  o += "constraint " + rng + "(X[a,k] > 0 -> N[a,k+1] = e[k+1]);\n";
  o += "constraint " + rng + "(X[a,k] = 0 -> N[a,k+1] = N[a,k]);\n";
  o += "constraint " + rng + "(e[k+1] - N[a,k] >= LO[X[a,k]] /\\ e[k+1] - N[a,k] <= HI[X[a,k]]);\n";
  o += "constraint " + rng + "(X[a,k] > 0 -> L[a,k] = FROM[X[a,k]]);\n";
  if (c.opts.redundant)
    o += "constraint forall(a in 1..NA, k in 0..H)(N[a,k] <= e[k]);  % redundant\n";
}

// A transition fires only when its guard holds on the stage before the event.
void EmitGuards(const Context& c) {
  c.out += "% guards\n";
  for (std::size_t a = 0; a < c.d.automata.size(); ++a) {
    const auto& au = c.d.automata[a];
    for (std::size_t k = 0; k < au.transitions.size(); ++k) {
      const Transition& t = au.transitions[k];
      if (IsTrue(t.guard)) continue;
      int id = c.info.transitions_of[a][k];
      c.out += "constraint forall(k in " + c.K0() + "..H-1)(X[" + std::to_string(a + 1) + ",k] = " +
               std::to_string(id) + " -> " +
               PrintCondition(c, t.guard, GuardInfo(), CondMode::kGuard) + ");\n";
    }
  }
}

// Commands. When only the automaton's own guards read its command, the command is the one the
// firing transition requires (a command that causes nothing is the no-op). Otherwise the
// command is free and a commanded transition whose guard holds must fire.
void EmitCommands(const Context& c) {
  c.out += "% commands\n";
  c.out += "constraint forall(a in 1..NA)(U[a,H] = 0);\n";
  for (std::size_t a = 0; a < c.d.automata.size(); ++a) {
    std::string A = std::to_string(a + 1);
    if (!c.info.command_public[a]) {
      c.out += "constraint forall(k in 0..H-1)(U[" + A + ",k] = CMD[X[" + A + ",k]]);\n";
      continue;
    }
    c.out += "constraint forall(k in 0..H-1)(U[" + A + ",k] <= NCMD[" + A + "]);\n";
    if (c.opts.history)
      c.out += "constraint forall(k in 0..P-1)(U[" + A + ",k] = CMD[X[" + A + ",k]]);\n";
    const auto& au = c.d.automata[a];
    for (std::size_t k = 0; k < au.transitions.size(); ++k) {
      const Transition& t = au.transitions[k];
      if (!t.commanded) continue;
      c.out += "constraint forall(k in " + c.K0() + "..H-1)((" + Enabled(c, static_cast<int>(a), t) +
               ") -> X[" + A + ",k] = " + std::to_string(c.info.transitions_of[a][k]) + ");\n";
    }
  }
}

// Automatic transitions fire as soon as they are enabled: the stage in which the guard holds
// ends no later than the moment the clock reaches lo, and the transition fires at that event.
// Controllable ones fire when the planner chooses, but no later than hi. Nothing is forced at
// or after the goal event g.
void EmitAutomatic(const Context& c) {
  c.out += "% automatic and controllable transitions\n";
  for (std::size_t a = 0; a < c.d.automata.size(); ++a) {
    const auto& au = c.d.automata[a];
    std::string A = std::to_string(a + 1);
    for (std::size_t k = 0; k < au.transitions.size(); ++k) {
      const Transition& t = au.transitions[k];
      if (t.commanded) continue;
      int id = c.info.transitions_of[a][k];
      std::string en = Enabled(c, static_cast<int>(a), t);
      if (t.controllable) {
        if (c.info.hi[id] < 0) continue;
        c.out += "constraint forall(k in " + c.K0() + "..H-1)(k < g -> ((" + en + ") -> e[k+1] - N[" + A +
                 ",k] <= " + std::to_string(c.info.hi[id]) + "));\n";
        continue;
      }
      long lo = c.info.lo[id];
      std::string fire = "X[" + A + ",k] = " + std::to_string(id);
      if (lo == 0) {
        c.out += "constraint forall(k in " + c.K0() + "..H-1)(k < g -> ((" + en + ") -> (e[k+1] = e[k] /\\ " +
                 fire + ")));\n";
      } else {
        std::string due = "N[" + A + ",k] + " + std::to_string(lo);
        c.out += "constraint forall(k in " + c.K0() + "..H-1)(k < g -> ((" + en + ") -> (e[k+1] <= max(e[k], " +
                 due + ") /\\ (e[k+1] >= " + due + " -> " + fire + "))));\n";
      }
    }
  }
}

// Concise runs: every event up to g carries a transition; after g nothing fires and the
// padding events keep e[g]'s time.
void EmitConcise(const Context& c) {
  c.out += "% concise runs\n";
  if (c.opts.idle_events)
    c.out += "constraint forall(k in " + c.K0() +
             "..H-1)(exists(a in 1..NA)(X[a,k] > 0) -> k < g);  % relaxed\n";
  else
    c.out += "constraint forall(k in " + c.K0() +
             "..H-1)((k < g) <-> exists(a in 1..NA)(X[a,k] > 0));\n";
  c.out += "constraint forall(k in 0..H-1)(k >= g -> e[k+1] = e[k]);\n";
}

// Redundant: entering L[a,k2] happens at least DIST[a, L[a,k1], L[a,k2]] after entering
// L[a,k1] (the shortest path over the transitions' lower durations; guards ignored, so it
// relaxes the automaton and is valid for every run). Lets propagation refute deadlines and
// bound the makespan as soon as the state plan's event indices are fixed.
void EmitTimeDistances(const Context& c) {
  std::string set;
  for (std::size_t a = 0; a < c.d.automata.size(); ++a) {
    bool timed = false;
    for (int id : c.info.transitions_of[a]) timed = timed || c.info.lo[id] > 0;
    if (timed) set += (set.empty() ? "" : ", ") + std::to_string(a + 1);
  }
  if (set.empty()) return;
  c.out += "% redundant: minimum time between entering two locations\n";
  c.out += "constraint forall(a in {" + set + "}, k1 in " + c.K0() + "..H-1, k2 in k1+1..H)(N[a,k2] >= "
           "N[a,k1] + DIST[a, L[a,k1], L[a,k2]]);\n";
}

void EmitAutomata(const Context& c) {
  EmitEvents(c);
  EmitLocationUpdate(c);
  EmitGuards(c);
  EmitCommands(c);
  EmitAutomatic(c);
  EmitConcise(c);
  if (c.opts.redundant) EmitTimeDistances(c);
  EmitSymmetry(c);
  c.out += "\n";
}

}  // namespace ctb::encode
