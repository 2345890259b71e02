#include "planner/search/history_nodes.h"

#include <cstddef>

namespace ctb::search {

namespace {

// Stage k of the history as a node after `prev` (stage k - 1): the monitors are not updated yet.
Node Stage(const Domain& d, const History& h, int k, const Node& prev) {
  Node n;
  n.parent = k - 1;
  n.event = k;
  n.time = h.times[k];
  n.cost = prev.cost;
  n.mon = prev.mon;
  for (std::size_t a = 0; a < d.automata.size(); ++a) {
    n.loc.push_back(h.locations[a][k]);
    n.entry.push_back(h.entry[a][k]);
  }
  for (const FiredTransition& f : h.fired) {
    if (f.event != k) continue;
    const Transition& tr = d.automata[f.automaton].transitions[f.transition];
    n.fired.emplace_back(f.automaton, f.transition);
    n.cost += tr.cost;
    // The command that caused it, on the stage before (as the exact engines' history reads it).
    if (tr.commanded && tr.command > 0) n.cmds_before.emplace_back(f.automaton, tr.command);
  }
  return n;
}

}  // namespace

std::vector<Node> HistoryNodes(const Expander& ex, const Domain& d, const History& h) {
  auto root = ex.Root();
  if (!root) return {};
  for (std::size_t a = 0; a < d.automata.size(); ++a)
    if (h.locations[a][0] != root->loc[a]) return {};  // a history from another initial state
  std::vector<Node> out;
  out.push_back(std::move(*root));
  for (int k = 1; k <= h.events(); ++k) {
    if (out.back().done) return {};  // accepted before the history's last stage
    Node n = Stage(d, h, k, out.back());
    if (!ex.Reported(&out.back(), n)) return {};
    out.push_back(std::move(n));
  }
  return out;
}

}  // namespace ctb::search
