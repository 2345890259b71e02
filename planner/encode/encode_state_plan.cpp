// Emitters for the state plan's accepting automata (thesis 3.5, contract section 3): episodes,
// temporal constraints, shared events, the maintenance constraint and the end state.
#include <cmath>
#include <string>
#include <vector>

#include "planner/encode/emit.h"
#include "planner/model/plan_cut.h"

namespace ctb::encode {

namespace {

// array[0..H] of var bool: NAME = [cond at k | k in 0..H];
void CondArray(const Context& c, const std::string& name, const Condition& cond, CondMode mode) {
  c.out += "array[0..H] of var bool: " + name + " = array1d(0..H, [" +
           PrintCondition(c, cond.expr, cond.info, mode) + " | k in 0..H]);\n";
}

std::string Bound(double seconds, const Context& c) {
  return std::to_string(std::lround(seconds * static_cast<double>(c.info.ticks_per_second)));
}

bool IsTrue(const Condition& cond) { return cond.expr.op == Expr::Op::kTrue; }

// The actions an order or a shared event reads as one event (AK[j]), and every action read.
void ActionUse(const StatePlan& sp, std::vector<bool>& at_one_event, std::vector<bool>& read) {
  at_one_event.assign(sp.actions.size(), false);
  read.assign(sp.actions.size(), false);
  auto end = [&](const OrderEnd& e) {
    if (e.action < 0) return;
    read[e.action] = true;
    if (sp.actions[e.action].occurrence != Occurrence::kEvery) at_one_event[e.action] = true;
  };
  for (const auto& o : sp.orders) {
    end(o.first);
    end(o.second);
  }
  for (const SharedEvent* ev : sp.AllSharedEvents())
    for (const auto& p : ev->endpoints)
      if (p.kind == EndpointKind::kAction) read[p.index] = at_one_event[p.index] = true;
  for (int j : sp.forbidden) read[j] = true;
}

// The model's variable for the event of a state-plan endpoint: shared events and cuts read it.
std::string EndpointVar(EndpointKind kind, int index) {
  const std::string i = std::to_string(index + 1);
  switch (kind) {
    case EndpointKind::kEpisodeStart: return "EP_S[" + i + "]";
    case EndpointKind::kEpisodeEnd: return "EP_E[" + i + "]";
    case EndpointKind::kEvent1: return "TC_1[" + i + "]";
    case EndpointKind::kEvent2: return "TC_2[" + i + "]";
    case EndpointKind::kAction: return "AK[" + i + "]";
    case EndpointKind::kOrder1: return "O_1[" + i + "]";
    case EndpointKind::kOrder2: return "O_2[" + i + "]";
  }
  return "0";
}

// "X[a,k] in {ids}": action j's transition fires between stage k and k+1.
std::string Fires(const Context& c, int j, const std::string& k) {
  const ActionEvent& act = c.sp.actions[j];
  std::string ids;
  for (int t : act.transitions)
    ids += (ids.empty() ? "" : ", ") + std::to_string(c.info.transitions_of[act.automaton][t]);
  return "X[" + std::to_string(act.automaton + 1) + "," + k + "] in {" + ids + "}";
}


}  // namespace

// Action events (contract section 15): ACT_j[k] when action j fires at event k; AK[j] its first
// or last firing when an order or a shared event reads it as one event; forbidden actions never
// fire after the history.
void EmitActions(const Context& c) {
  if (c.sp.actions.empty()) return;
  std::vector<bool> one, read;
  ActionUse(c.sp, one, read);
  std::string& o = c.out;
  o += "% action events\n";
  o += "array[1.." + std::to_string(c.sp.actions.size()) + "] of var 0..H: AK;\n";
  for (std::size_t j = 0; j < c.sp.actions.size(); ++j) {
    const std::string J = std::to_string(j + 1), act = "ACT_" + J;
    if (!read[j]) {
      o += "constraint AK[" + J + "] = 0;\n";
      continue;
    }
    o += "array[0..H] of var bool: " + act + " = array1d(0..H, [if k = 0 then false else " +
         Fires(c, static_cast<int>(j), "k-1") + " endif | k in 0..H]);\n";
    if (!one[j]) {
      o += "constraint AK[" + J + "] = 0;\n";
      continue;
    }
    const bool last = c.sp.actions[j].occurrence == Occurrence::kLast;
    o += "constraint " + act + "[AK[" + J + "]] /\\ forall(k in 0..H)(k " + (last ? ">" : "<") +
         " AK[" + J + "] -> not " + act + "[k]);\n";
  }
  for (int j : c.sp.forbidden)
    o += "constraint forall(k in " + c.K0() + "..H-1)(not (" + Fires(c, j, "k") + "));\n";
}

// Orders (state_plan.h Order): O_1 and O_2 are the events of their two ends, O_B the event at
// which the order is accepted (the end state waits for it).
void EmitOrders(const Context& c) {
  const int n = static_cast<int>(c.sp.orders.size());
  if (n == 0) return;
  std::string& o = c.out;
  const std::string N = std::to_string(n);
  o += "% orders\n";
  for (const char* v : {"O_1", "O_2", "O_B"}) o += "array[1.." + N + "] of var 0..H: " + std::string(v) + ";\n";
  for (int q = 0; q < n; ++q) {
    const Order& ord = c.sp.orders[q];
    const std::string Q = std::to_string(q + 1), o1 = "O_1[" + Q + "]", o2 = "O_2[" + Q + "]";
    const std::string lb = Bound(ord.lower, c);
    const bool every = ord.second.action >= 0 &&
                       c.sp.actions[ord.second.action].occurrence == Occurrence::kEvery;
    if (ord.first.action >= 0) o += "constraint " + o1 + " = AK[" + std::to_string(ord.first.action + 1) + "];\n";
    if (ord.second.action >= 0 && !every)
      o += "constraint " + o2 + " = AK[" + std::to_string(ord.second.action + 1) + "];\n";
    auto within = [&](const std::string& dt) {
      std::string s = dt + " >= " + lb;
      if (ord.upper) s += " /\\ " + dt + " <= " + Bound(*ord.upper, c);
      return s;
    };
    if (ord.ordered) {
      const std::string after = ord.strict ? " > " : " >= ";
      if (ord.first.action < 0) {
        CondArray(c, "O_C1_" + Q, ord.first.condition, CondMode::kEvent);
        o += "constraint O_C1_" + Q + "[" + o1 + "] /\\ forall(k in 0..H)(k < " + o1 + " -> not O_C1_" + Q + "[k]);\n";
      }
      if (every) {
        const std::string act = "ACT_" + std::to_string(ord.second.action + 1);
        o += "constraint forall(k in 0..H)(" + act + "[k] -> (k" + after + o1 + " /\\ " +
             within("e[k] - e[" + o1 + "]") + "));\n";
        o += "constraint " + o2 + " >= " + o1 + " /\\ forall(k in 0..H)(" + act + "[k] -> k <= " + o2 +
             ") /\\ (" + o2 + " > " + o1 + " -> " + act + "[" + o2 + "]);\n";
        o += "constraint O_B[" + Q + "] = " + o1 + ";\n";
        continue;
      }
      o += "constraint " + o2 + after + o1 + " /\\ " + within("e[" + o2 + "] - e[" + o1 + "]") + ";\n";
      if (ord.second.action < 0) {
        const std::string c2 = "O_C2_" + Q;
        CondArray(c, c2, ord.second.condition, CondMode::kEvent);
        o += "constraint " + c2 + "[" + o2 + "] /\\ forall(k in 0..H)((k" + after + o1 + " /\\ k < " + o2 +
             ") -> not (" + c2 + "[k] /\\ e[k] - e[" + o1 + "] >= " + lb + "));\n";
      }
      o += "constraint O_B[" + Q + "] = " + o2 + ";\n";
      continue;
    }
    // Either order, at least one end an action.
    const OrderEnd* cond = ord.first.action < 0 ? &ord.first : ord.second.action < 0 ? &ord.second : nullptr;
    if (cond) {
      const std::string oc = cond == &ord.first ? o1 : o2, ox = cond == &ord.first ? o2 : o1;
      const std::string cc = "O_CC_" + Q;
      CondArray(c, cc, cond->condition, CondMode::kEvent);
      o += "constraint " + cc + "[" + oc + "] /\\ forall(k in 0..H)((k <= " + ox + " /\\ k < " + oc +
           ") -> not " + cc + "[k]);\n";
      o += "constraint forall(k in 0..H)((k > " + ox + " /\\ k < " + oc + ") -> not (" + cc +
           "[k] /\\ e[k] - e[" + ox + "] >= " + lb + "));\n";
    }
    o += "constraint " + within("abs(e[" + o2 + "] - e[" + o1 + "])") + ";\n";
    o += "constraint O_B[" + Q + "] = max(" + o1 + ", " + o2 + ");\n";
  }
}

// Episode p starts at the first event at which its accepting condition holds (EP_S), ends at a
// later event of the planner's choice (EP_E) no later than g, lasts within its bounds, and its
// state constraint holds on every stage from start to end.
void EmitEpisodes(const Context& c) {
  const int n = static_cast<int>(c.sp.episodes.size());
  if (n == 0) return;
  std::string& o = c.out;
  o += "% episodes\n";
  o += "array[1.." + std::to_string(n) + "] of var 0..H: EP_S;\n";
  o += "array[1.." + std::to_string(n) + "] of var 0..H: EP_E;\n";
  o += "array[1.." + std::to_string(n) + ", 0..H] of var 0..3: EPSTATE;\n";
  for (int p = 0; p < n; ++p) {
    const Episode& ep = c.sp.episodes[p];
    std::string P = std::to_string(p + 1), acc = "EP_ACC_" + P, st = "EP_ST_" + P;
    CondArray(c, acc, ep.accepting, CondMode::kEvent);
    o += "constraint " + acc + "[EP_S[" + P + "]] /\\ forall(k in 0..H)(k < EP_S[" + P +
         "] -> not " + acc + "[k]);\n";
    o += "constraint EP_S[" + P + "] < EP_E[" + P + "] /\\ EP_E[" + P + "] <= g;\n";
    o += "constraint e[EP_E[" + P + "]] - e[EP_S[" + P + "]] >= " + Bound(ep.lower, c) +
         " /\\ e[EP_E[" + P + "]] - e[EP_S[" + P + "]] <= " + Bound(ep.upper, c) + ";\n";
    if (!IsTrue(ep.state)) {
      CondArray(c, st, ep.state, CondMode::kStage);
      o += "constraint forall(k in 0..H)((k >= EP_S[" + P + "] /\\ k < EP_E[" + P + "]) -> " + st +
           "[k]);\n";
    }
    o += "constraint forall(k in 0..H)(EPSTATE[" + P + ",k] = bool2int(k >= EP_S[" + P +
         "]) + bool2int(k >= EP_E[" + P + "]));\n";
  }
}

// Temporal constraint q: TC_1 and TC_2 are the events at which its two conditions count. It
// becomes active at the first event at which either holds (TC_A = min) and is accepted at the
// other (TC_B = max) no later than g, with e[TC_B] - e[TC_A] within the bounds. Both at the
// first event: accepted at once when the lower bound is 0, failed otherwise.
void EmitTemporals(const Context& c) {
  const int n = static_cast<int>(c.sp.temporals.size());
  if (n == 0) return;
  std::string& o = c.out;
  std::string N = std::to_string(n);
  o += "% temporal constraints\n";
  for (const char* v : {"TC_1", "TC_2", "TC_A", "TC_B"})
    o += "array[1.." + N + "] of var 0..H: " + std::string(v) + ";\n";
  o += "array[1.." + N + ", 0..H] of var 0..3: TCSTATE;\n";
  for (int q = 0; q < n; ++q) {
    const Temporal& tc = c.sp.temporals[q];
    std::string Q = std::to_string(q + 1), c1 = "TC_C1_" + Q, c2 = "TC_C2_" + Q;
    CondArray(c, c1, tc.event1, CondMode::kEvent);
    CondArray(c, c2, tc.event2, CondMode::kEvent);
    o += "constraint " + c1 + "[TC_1[" + Q + "]] /\\ " + c2 + "[TC_2[" + Q + "]];\n";
    o += "constraint TC_A[" + Q + "] = min(TC_1[" + Q + "], TC_2[" + Q + "]) /\\ TC_B[" + Q +
         "] = max(TC_1[" + Q + "], TC_2[" + Q + "]);\n";
    o += "constraint forall(k in 0..H)(k < TC_A[" + Q + "] -> not (" + c1 + "[k] \\/ " + c2 +
         "[k]));\n";
    std::string both = "(" + c1 + "[TC_A[" + Q + "]] /\\ " + c2 + "[TC_A[" + Q + "]])";
    if (tc.lower > 0)
      o += "constraint not " + both + ";\n";
    else
      o += "constraint " + both + " <-> TC_1[" + Q + "] = TC_2[" + Q + "];\n";
    o += "constraint TC_B[" + Q + "] <= g;\n";
    o += "constraint e[TC_B[" + Q + "]] - e[TC_A[" + Q + "]] >= " + Bound(tc.lower, c) +
         " /\\ e[TC_B[" + Q + "]] - e[TC_A[" + Q + "]] <= " + Bound(tc.upper, c) + ";\n";
    o += "constraint forall(k in 0..H)(TCSTATE[" + Q + ",k] = bool2int(k >= TC_A[" + Q +
         "]) + bool2int(k >= TC_B[" + Q + "]));\n";
  }
}

// Shared events: every endpoint of one entry falls on the same event.
void EmitSharedEvents(const Context& c) {
  if (c.sp.events.empty() && c.sp.action_events.empty()) return;
  c.out += "% shared events\n";
  auto var = [](const Endpoint& p) { return EndpointVar(p.kind, p.index); };
  for (const SharedEvent* ev : c.sp.AllSharedEvents())
    for (std::size_t k = 1; k < ev->endpoints.size(); ++k)
      c.out += "constraint " + var(ev->endpoints[0]) + " = " + var(ev->endpoints[k]) + ";\n";
}

// The end state is accepted at g, the first event at which the goal holds and every episode and
// temporal constraint has been accepted; the maintenance constraint holds on every stage before.
void EmitEndState(const Context& c) {
  std::string& o = c.out;
  o += "% end state\n";
  CondArray(c, "GOAL", c.sp.goal, CondMode::kEvent);
  std::string done = "GOAL[k]";
  if (!c.sp.episodes.empty()) done += " /\\ forall(p in index_set(EP_E))(EP_E[p] <= k)";
  if (!c.sp.temporals.empty()) done += " /\\ forall(q in index_set(TC_B))(TC_B[q] <= k)";
  if (!c.sp.orders.empty()) done += " /\\ forall(q in index_set(O_B))(O_B[q] <= k)";
  o += "array[0..H] of var bool: DONE = array1d(0..H, [" + done + " | k in 0..H]);\n";
  o += "constraint DONE[g] /\\ forall(k in 0..H)(k < g -> not DONE[k]);\n";
  if (!IsTrue(c.sp.maintenance)) {
    CondArray(c, "MAINT", c.sp.maintenance, CondMode::kStage);
    o += "constraint forall(k in 0..H)(k < g -> MAINT[k]);\n";
  }
}

namespace {

// The model's variable for a mark's event.
std::string MarkVar(const CutMark& m) { return EndpointVar(m.endpoint, m.index); }

// "not (every literal)" for one assignment of the loop classes (plan_cut.h): each point's
// transition fires at its class's event, the marks, orders and neighbours are as in the cut.
std::string CutConstraint(const Context& c, const PlanCut& cut) {
  const CutShape s = ShapeOf(cut);
  std::vector<std::string> ev(s.pins.size());
  for (int k : s.order) {
    const CutPin& p = s.pins[k];
    const std::string A = std::to_string(p.automaton + 1);
    switch (p.kind) {
      case CutPin::Kind::kLoop: ev[k] = "k" + std::to_string(k); break;
      case CutPin::Kind::kOrigin: ev[k] = "0"; break;
      case CutPin::Kind::kMark: ev[k] = MarkVar(cut.marks[p.mark]); break;
      case CutPin::Kind::kGoal: ev[k] = "g"; break;
      case CutPin::Kind::kAfter: ev[k] = "NXT[" + A + "," + ev[p.from_class] + "]"; break;
      case CutPin::Kind::kBefore: ev[k] = "PREV[" + A + ",max(" + ev[p.from_class] + ",1)-1]"; break;
    }
  }
  auto E = [&](int point) { return ev[s.class_of[point]]; };
  std::vector<std::string> lits;
  for (std::size_t p = 0; p < cut.points.size(); ++p) {
    const CutPoint& pt = cut.points[p];
    const std::string e = E(static_cast<int>(p));
    if (pt.automaton < 0) {
      lits.push_back(e + " = 0");
      continue;
    }
    lits.push_back(e + " >= 1 /\\ " + e + " <= H /\\ X[" + std::to_string(pt.automaton + 1) + ",max(min(" +
                   e + ",H),1)-1] = " + std::to_string(c.info.transitions_of[pt.automaton][pt.transition]));
  }
  for (const CutMark& m : cut.marks)
    lits.push_back(E(m.point) + " = " + (m.kind == CutMark::Kind::kGoal ? "g" : MarkVar(m)));
  for (auto [x, y] : cut.before) lits.push_back(E(x) + " < " + E(y));
  for (auto [x, y] : DistinctPairs(cut)) lits.push_back(E(x) + " != " + E(y));
  for (auto [x, b] : cut.quiet)
    lits.push_back("X[" + std::to_string(b + 1) + ",max(min(" + E(x) + ",H),1)-1] = 0");
  for (auto [x, y] : cut.next) {
    const std::string A = std::to_string(cut.points[y].automaton + 1);
    lits.push_back(E(y) + " = NXT[" + A + "," + E(x) + "]");
  }
  for (int y : cut.first) {
    const std::string A = std::to_string(cut.points[y].automaton + 1);
    lits.push_back("PREV[" + A + ",max(" + E(y) + ",1)-1] = 0");
  }
  for (int x : cut.last) {
    const std::string A = std::to_string(cut.points[x].automaton + 1);
    lits.push_back("NXT[" + A + "," + E(x) + "] = H+1");
  }
  std::string conj;
  for (const auto& l : lits) conj += (conj.empty() ? "(" : " /\\ (") + l + ")";
  std::string loops;
  for (int k : s.loops) loops += (loops.empty() ? "" : ", ") + std::string("k") + std::to_string(k) + " in 1..H";
  if (loops.empty()) return "not (" + conj + ")";
  return "forall(" + loops + ")(not (" + conj + "))";
}

}  // namespace

// Cuts of the conflict-directed search among plans (state_plan.h PlanCut, plan_cut.h). PREV[a,k]:
// the event of a's last transition at or before event k (0: none); NXT[a,k]: of its first after
// k (H+1: none).
void EmitCuts(const Context& c) {
  if (c.sp.cuts.empty()) return;
  std::string& o = c.out;
  o += "% cuts of the search among plans (controllability conflicts)\n";
  o += "array[1..NA, 0..H] of var 0..H: PREV;\n";
  o += "array[1..NA, 0..H] of var 1..H+1: NXT;\n";
  o += "constraint forall(a in 1..NA)(PREV[a,0] = 0 /\\ NXT[a,H] = H+1);\n";
  o += "constraint forall(a in 1..NA, k in 1..H)(PREV[a,k] = if X[a,k-1] > 0 then k else PREV[a,k-1] endif);\n";
  o += "constraint forall(a in 1..NA, k in 0..H-1)(NXT[a,k] = if X[a,k] > 0 then k+1 else NXT[a,k+1] endif);\n";
  for (const PlanCut& cut : c.sp.cuts) o += "constraint " + CutConstraint(c, cut) + ";\n";
}

void EmitStatePlan(const Context& c) {
  EmitEpisodes(c);
  EmitTemporals(c);
  EmitActions(c);
  EmitOrders(c);
  EmitSharedEvents(c);
  EmitEndState(c);
  EmitCuts(c);
  c.out += "\n";
}

}  // namespace ctb::encode
