// Emitters for the state plan's accepting automata (thesis 3.5, contract section 3): episodes,
// temporal constraints, shared events, the maintenance constraint and the end state.
#include <cmath>
#include <string>

#include "planner/encode/emit.h"

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

}  // namespace

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
  if (c.sp.events.empty()) return;
  c.out += "% shared events\n";
  auto var = [](const Endpoint& p) {
    std::string i = std::to_string(p.index + 1);
    switch (p.kind) {
      case EndpointKind::kEpisodeStart: return "EP_S[" + i + "]";
      case EndpointKind::kEpisodeEnd: return "EP_E[" + i + "]";
      case EndpointKind::kEvent1: return "TC_1[" + i + "]";
      case EndpointKind::kEvent2: return "TC_2[" + i + "]";
    }
    return std::string("0");
  };
  for (const auto& ev : c.sp.events)
    for (std::size_t k = 1; k < ev.endpoints.size(); ++k)
      c.out += "constraint " + var(ev.endpoints[0]) + " = " + var(ev.endpoints[k]) + ";\n";
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
  o += "array[0..H] of var bool: DONE = array1d(0..H, [" + done + " | k in 0..H]);\n";
  o += "constraint DONE[g] /\\ forall(k in 0..H)(k < g -> not DONE[k]);\n";
  if (!IsTrue(c.sp.maintenance)) {
    CondArray(c, "MAINT", c.sp.maintenance, CondMode::kStage);
    o += "constraint forall(k in 0..H)(k < g -> MAINT[k]);\n";
  }
}

void EmitStatePlan(const Context& c) {
  EmitEpisodes(c);
  EmitTemporals(c);
  EmitSharedEvents(c);
  EmitEndState(c);
  c.out += "\n";
}

}  // namespace ctb::encode
