// The objective as z3 terms: the counterpart of planner/encode/encode_objective.cpp. Search
// annotations have no counterpart; of the redundant constraints only "cost >= MINCOST * g" is
// kept (the distance tables are lookups at variable indices, costly to unfold).
#include "planner/smt/z3_model.h"

namespace ctb::smt {

void AddObjective(Model& m) {
  z3::expr_vector terms(m.z);
  for (std::size_t a = 0; a < m.d.automata.size(); ++a) {
    const Automaton& au = m.d.automata[a];
    const auto& ids = m.info.transitions_of[a];
    for (int k = 0; k < m.H; ++k) {
      // The cost of the transition at event k+1 (0 for none).
      z3::expr c = m.Int("C_" + std::to_string(a) + "_" + std::to_string(k));
      m.Add(z3::implies(m.X[a][k] == 0, c == 0));
      for (std::size_t i = 0; i < ids.size(); ++i)
        m.Add(z3::implies(m.X[a][k] == ids[i], c == m.Val(au.transitions[i].cost)));
      terms.push_back(c);
    }
  }
  m.cost = terms.empty() ? m.z.int_val(0) : z3::sum(terms);
  m.makespan = m.e[m.H];  // padding events keep e[g]'s time
  if (m.opts.redundant && !m.opts.idle_events) m.Add(m.cost >= m.Val(m.info.min_cost) * m.g);
  auto [cost_factor, makespan_factor] = ObjectiveFactors(m.opts.objective, m.T);
  m.objective = m.Val(cost_factor) * m.cost + m.Val(makespan_factor) * m.makespan;
  if (m.opts.better_than) m.Add(m.objective < m.Val(*m.opts.better_than));
}

}  // namespace ctb::smt
