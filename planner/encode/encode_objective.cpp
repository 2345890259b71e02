// The objective (thesis 3.6, contract section 3) and the search strategy.
#include <string>
#include <tuple>

#include "planner/encode/emit.h"

namespace ctb {

std::pair<long, long> ObjectiveFactors(Objective objective, long time_bound) {
  switch (objective) {
    case Objective::kCost: return {1, 0};
    case Objective::kMakespan: return {0, 1};
    case Objective::kCostThenMakespan: return {time_bound + 1, 1};
  }
  return {1, 0};
}

}  // namespace ctb

namespace ctb::encode {

// Branching in time order: for each event, which transition each automaton takes (no
// transition first, so that shorter plans are tried first), then the event's time (earliest
// first); then the state plan's free choices.
std::string TimeOrderSearch(const Context& c) {
  // The state plan's event indices first (smallest first): once they are fixed the accepting
  // conditions and time bounds bite directly. Then transitions event by event (no transition
  // first, so shorter plans come first); times last, by halving (given the transitions, times
  // form a simple temporal network that propagation nearly fixes).
  //   g_first:  g, episodes, temporal constraints   (closes makespan proofs fast)
  //   tc_first: temporal constraints, episodes, g   (refutes impossible constraints fast)
  const std::string& s = c.opts.search;
  std::string ep = c.sp.episodes.empty() ? "" : "EP_S ++ EP_E ++ ";
  std::string tc = c.sp.temporals.empty() ? "" : "TC_1 ++ TC_2 ++ ";
  if (!c.sp.orders.empty()) tc += "O_1 ++ O_2 ++ ";
  std::string idx = s == "g_first" ? "[g] ++ " + ep + tc + "[]" : tc + ep + "[g]";
  std::string var_sel = s == "first_fail" ? "first_fail" : "input_order";
  std::string plan = "int_search(" + idx + ", " + var_sel + ", indomain_min), ";
  std::string xs = "int_search([X[a,k] | k in 0..H-1, a in 1..NA], input_order, indomain_min), ";
  std::string times = "int_search(e, input_order, indomain_split)";
  if (s == "transitions_first") return ":: seq_search([" + xs + plan + times + "])";
  return ":: seq_search([" + plan + xs + times + "])";
}

void EmitObjectiveAndSearch(const Context& c, Encoding& enc) {
  std::string& o = c.out;
  o += "% objective\n";
  // Prefix costs per automaton, with the cheapest way from each stage's location to the final
  // one as a lower bound on what remains (an admissible cost-to-go for branch and bound).
  o += "array[1..NA, 0..H] of var 0..MAXCOST: CS;\n";
  o += "constraint forall(a in 1..NA)(CS[a,0] = 0);\n";
  o += "constraint forall(a in 1..NA, k in 0..H-1)(CS[a,k+1] = CS[a,k] + COST[X[a,k]]);\n";
  if (c.opts.redundant)
    o += "constraint forall(a in 1..NA, k in " + c.K0() + "..H-1)(CS[a,H] - CS[a,k] >= "
         "CDIST[a, L[a,k], L[a,H]]);  % redundant\n";
  // Several automata may fire at one event: the total is bounded by NA times one's bound.
  o += "var 0..NA*MAXCOST: cost = sum(a in 1..NA)(CS[a,H]);\n";
  o += "var 0..T: makespan = e[H];  % padding events keep e[g]'s time\n";
  if (c.opts.redundant && !c.opts.idle_events && !c.opts.history)
    o += "constraint cost >= MINCOST * g;  % redundant: every event carries a transition\n";
  if (c.opts.redundant && !c.opts.idle_events && c.opts.history)
    o += "constraint cost - sum(a in 1..NA)(CS[a,P]) >= MINCOST * (g - P);  % redundant\n";
  std::tie(enc.objective_cost_factor, enc.objective_makespan_factor) =
      ObjectiveFactors(c.opts.objective, enc.time_bound);
  std::string obj = c.opts.objective == Objective::kCost       ? "cost"
                    : c.opts.objective == Objective::kMakespan ? "makespan"
                    : "cost * " + std::to_string(enc.objective_cost_factor) + " + makespan";
  o += "var int: objective = " + obj + ";\n";
  if (c.opts.at_least && *c.opts.at_least > 0)
    o += "constraint objective >= " + std::to_string(*c.opts.at_least) + ";  % redundant: a proven bound\n";
  if (c.opts.better_than) o += "constraint objective < " + std::to_string(*c.opts.better_than) + ";\n";
  std::string search = c.opts.search == "default" ? "" : TimeOrderSearch(c);
  if (c.opts.minimize_changes) {
    o += MinChangeSolve(c);
    return;
  }
  o += "solve " + search + " minimize objective;\n";
}

}  // namespace ctb::encode
