// The objective as z3 terms: the counterpart of planner/encode/encode_objective.cpp. Search
// annotations have no counterpart; of the redundant constraints only "cost >= MINCOST * g" is
// kept (the distance tables are lookups at variable indices, costly to unfold), with the
// proven lower bound (EncodeOptions::at_least) as MiniZinc has it.
#include "planner/smt/z3_model.h"

namespace ctb::smt {

void AddObjective(Model& m) {
  z3::expr_vector terms(m.z);
  for (std::size_t a = 0; a < m.d.automata.size(); ++a) {
    const Automaton& au = m.d.automata[a];
    for (int k = 0; k < m.H; ++k)
      for (std::size_t i = 0; i < au.transitions.size(); ++i)
        terms.push_back(z3::ite(m.fire[a][k][i], m.Val(au.transitions[i].cost), m.Val(0)));
  }
  m.cost = terms.empty() ? m.z.int_val(0) : z3::sum(terms);
  m.makespan = m.e[m.H];  // padding events keep e[g]'s time
  if (m.opts.redundant && !m.opts.idle_events) {  // cost >= MINCOST * g
    z3::expr_vector events(m.z);
    for (const auto& gt : m.g.gt) events.push_back(z3::ite(gt, m.Val(1), m.Val(0)));
    if (!events.empty()) m.Add(m.cost >= m.Val(m.info.min_cost) * z3::sum(events));
  }
  auto [cost_factor, makespan_factor] = ObjectiveFactors(m.opts.objective, m.T);
  m.objective = m.Val(cost_factor) * m.cost + m.Val(makespan_factor) * m.makespan;
  if (m.opts.at_least && *m.opts.at_least > 0)  // redundant: a proven bound
    m.Add(m.objective >= m.Val(*m.opts.at_least));
  if (m.opts.better_than) m.Add(m.objective < m.Val(*m.opts.better_than));
}

}  // namespace ctb::smt
