#include "planner/solve/decompose.h"

#include <algorithm>
#include <map>
#include <numeric>

#include "planner/expr/expr_print.h"
#include "planner/expr/normalize.h"

namespace ctb {

namespace {

struct UnionFind {
  std::vector<int> p;
  explicit UnionFind(std::size_t n) : p(n) { std::iota(p.begin(), p.end(), 0); }
  int Find(int x) { return p[x] == x ? x : p[x] = Find(p[x]); }
  void Join(int a, int b) { p[Find(a)] = Find(b); }
};

void Conjuncts(const Expr& e, std::vector<const Expr*>& out) {
  if (e.op == Expr::Op::kAnd) {
    Conjuncts(e.kids[0], out);
    Conjuncts(e.kids[1], out);
  } else if (e.op != Expr::Op::kTrue) {
    out.push_back(&e);
  }
}

// Renames the automata, episodes and temporal constraints an expression reads to a part's
// indices.
struct Remap {
  const std::vector<int>& automaton;
  const std::vector<int>& episode;
  const std::vector<int>& temporal;

  void operator()(Expr& e) const {
    for (auto& k : e.kids) (*this)(k);
    if (e.op != Expr::Op::kAtom) return;
    switch (e.var_kind) {
      case VarKind::kLocation:
      case VarKind::kCommand: e.target = automaton[e.target]; break;
      case VarKind::kEpisodeState: e.target = episode[e.target]; break;
      case VarKind::kTemporalState: e.target = temporal[e.target]; break;
      case VarKind::kUnresolved: break;
    }
  }
  // A part's conditions are their normalised trees (which mean what the originals do, with the
  // original classification kept in info): the originals may read automata of other parts
  // inside a tautology. The merged plan is verified against the originals.
  void operator()(Condition& c) const {
    (*this)(c.expr);
    c.raw = c.expr;
    c.raw_info = c.info;
    ExprInfo reads = InfoOf(c.expr);
    reads.domain_uses_i = c.info.domain_uses_i;
    reads.domain_uses_i1 = c.info.domain_uses_i1;
    reads.uses_fixed = c.info.uses_fixed;
    c.info = reads;
    c.raw_info = reads;
  }
};

Condition TrueCondition(const std::string& pointer) {
  Condition c;
  c.text = "true";
  c.pointer = pointer;
  return c;
}

}  // namespace

std::vector<SubProblem> SplitProblem(const Domain& d, const StatePlan& sp) {
  if (sp.maintenance.expr.op != Expr::Op::kTrue) return {};
  // Actions ordered or forbidden (contract section 15) are solved as one model.
  if (sp.HasActionRules()) return {};
  // Splitting a change condition's conjuncts would turn each into a state condition.
  if (sp.goal.info.IsChange()) return {};
  const int na = static_cast<int>(d.automata.size());
  const int ne = static_cast<int>(sp.episodes.size()), nq = static_cast<int>(sp.temporals.size());
  std::vector<const Expr*> goal;
  Conjuncts(sp.goal.expr, goal);
  const int ng = static_cast<int>(goal.size());
  // Nodes: automata, episodes, temporals, goal conjuncts.
  auto ep = [&](int p) { return na + p; };
  auto tc = [&](int q) { return na + ne + q; };
  auto gc = [&](int c) { return na + ne + nq + c; };
  UnionFind uf(na + ne + nq + ng);
  auto link = [&](int node, const ExprInfo& info) {
    for (int a : info.locations_read) uf.Join(node, a);
    for (int a : info.commands_read) uf.Join(node, a);
    for (int p : info.episodes_read) uf.Join(node, ep(p));
    for (int q : info.temporals_read) uf.Join(node, tc(q));
  };
  for (int a = 0; a < na; ++a)
    for (const auto& t : d.automata[a].transitions) link(a, t.guard_info);
  for (int p = 0; p < ne; ++p) {
    link(ep(p), sp.episodes[p].accepting.info);
    link(ep(p), sp.episodes[p].state.info);
  }
  for (int q = 0; q < nq; ++q) {
    link(tc(q), sp.temporals[q].event1.info);
    link(tc(q), sp.temporals[q].event2.info);
  }
  for (int c = 0; c < ng; ++c) {
    link(gc(c), InfoOf(*goal[c]));
  }
  for (const auto& ev : sp.events)
    for (const auto& x : ev.endpoints) {
      const auto& y = ev.endpoints[0];
      auto node = [&](const Endpoint& e) {
        return e.kind == EndpointKind::kEpisodeStart || e.kind == EndpointKind::kEpisodeEnd
                   ? ep(e.index) : tc(e.index);
      };
      uf.Join(node(x), node(y));
    }
  // An automaton without transitions keeps its initial location: it is solved with the first
  // automaton that has some (an imported PDDL model's variables that no relevant action changes
  // were each a part of their own, so the first-plan engine, which runs on unsplit problems only,
  // never ran on the rest).
  int mover = -1;
  for (int a = 0; a < na && mover < 0; ++a)
    if (!d.automata[a].transitions.empty()) mover = a;
  if (mover >= 0)
    for (int a = 0; a < na; ++a)
      if (d.automata[a].transitions.empty()) uf.Join(a, mover);
  // Components that hold automata; pieces without automata go to the first component.
  std::map<int, int> part_of_root;
  std::vector<std::vector<int>> automata;
  for (int a = 0; a < na; ++a) {
    int r = uf.Find(a);
    if (!part_of_root.count(r)) {
      part_of_root[r] = static_cast<int>(automata.size());
      automata.emplace_back();
    }
    automata[part_of_root[r]].push_back(a);
  }
  if (automata.size() < 2) return {};
  auto part = [&](int node) {
    auto it = part_of_root.find(uf.Find(node));
    return it == part_of_root.end() ? 0 : it->second;
  };
  std::vector<SubProblem> parts(automata.size());
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const int kk = static_cast<int>(k);
    SubProblem& sub = parts[k];
    sub.automata = automata[k];
    std::vector<int> local(na, -1), ep_local(ne, -1), tc_local(nq, -1);
    for (std::size_t j = 0; j < sub.automata.size(); ++j) local[sub.automata[j]] = static_cast<int>(j);
    for (int p = 0; p < ne; ++p)
      if (part(ep(p)) == kk) {
        ep_local[p] = static_cast<int>(sub.episode_map.size());
        sub.episode_map.push_back(p);
      }
    for (int q = 0; q < nq; ++q)
      if (part(tc(q)) == kk) {
        tc_local[q] = static_cast<int>(sub.temporal_map.size());
        sub.temporal_map.push_back(q);
      }
    // Every name an expression of this part reads is in the part (that is how parts are made).
    Remap remap{local, ep_local, tc_local};
    Domain& sd = sub.domain;
    sd.name = d.name + "_part" + std::to_string(k + 1);
    sd.description = d.description;
    sd.time_resolution = d.time_resolution;
    StatePlan& ssp = sub.plan;
    ssp.objective = sp.objective;
    for (int a : sub.automata) {
      Automaton au = d.automata[a];
      for (auto& t : au.transitions) {
        remap(t.guard);
        t.guard_info = InfoOf(t.guard);
      }
      sd.automata.push_back(std::move(au));
      ssp.initial.push_back(sp.initial[a]);
    }
    ssp.maintenance = TrueCondition(sp.maintenance.pointer);
    ssp.goal = TrueCondition(sp.goal.pointer);
    for (int c = 0; c < ng; ++c) {
      if (part(gc(c)) != kk) continue;
      ssp.goal.text = (ssp.goal.expr.op == Expr::Op::kTrue ? "" : ssp.goal.text + " /\\ ") +
                      PrintSource(*goal[c]);
      Expr e = *goal[c];
      remap(e);
      if (ssp.goal.expr.op == Expr::Op::kTrue) {
        ssp.goal.expr = std::move(e);
      } else {
        Expr both;
        both.op = Expr::Op::kAnd;
        both.kids = {std::move(ssp.goal.expr), std::move(e)};
        ssp.goal.expr = std::move(both);
      }
    }
    ssp.goal.info = InfoOf(ssp.goal.expr);  // a state condition: change goals are never split
    ssp.goal.raw = ssp.goal.expr;
    ssp.goal.raw_info = ssp.goal.info;
    for (int p : sub.episode_map) {
      Episode e = sp.episodes[p];
      remap(e.accepting);
      remap(e.state);
      ssp.episodes.push_back(std::move(e));
    }
    for (int q : sub.temporal_map) {
      Temporal t = sp.temporals[q];
      remap(t.event1);
      remap(t.event2);
      ssp.temporals.push_back(std::move(t));
    }
    for (const auto& ev : sp.events) {
      const Endpoint& e0 = ev.endpoints[0];
      const bool is_ep = e0.kind == EndpointKind::kEpisodeStart || e0.kind == EndpointKind::kEpisodeEnd;
      if (part(is_ep ? ep(e0.index) : tc(e0.index)) != kk) continue;
      SharedEvent se = ev;
      for (auto& x : se.endpoints) {
        const bool x_ep = x.kind == EndpointKind::kEpisodeStart || x.kind == EndpointKind::kEpisodeEnd;
        x.index = x_ep ? ep_local[x.index] : tc_local[x.index];
      }
      ssp.events.push_back(std::move(se));
    }
  }
  return parts;
}

Trajectory MergeTrajectories(const std::vector<SubProblem>& parts,
                             const std::vector<Trajectory>& plans, const Domain& d,
                             const StatePlan& sp) {
  // Local events (part, k >= 1) sorted by (time, rank among the part's events at that time).
  struct Local {
    long time;
    int rank;
    std::size_t part;
    int k;
  };
  std::vector<Local> locals;
  for (std::size_t p = 0; p < parts.size(); ++p) {
    const auto& ev = plans[p].events;
    int rank = 0;
    for (int k = 1; k < static_cast<int>(ev.size()); ++k) {
      rank = (k > 1 && ev[k] == ev[k - 1]) ? rank + 1 : 0;
      locals.push_back({ev[k], rank, p, k});
    }
  }
  std::sort(locals.begin(), locals.end(), [](const Local& a, const Local& b) {
    return a.time != b.time ? a.time < b.time : a.rank < b.rank;
  });
  // merged[p][k]: merged event index of part p's event k.
  std::vector<std::vector<int>> merged(parts.size());
  for (std::size_t p = 0; p < parts.size(); ++p) merged[p].assign(plans[p].events.size(), 0);
  Trajectory t;
  t.events = {0};
  for (std::size_t i = 0; i < locals.size(); ++i) {
    bool same = i > 0 && locals[i].time == locals[i - 1].time && locals[i].rank == locals[i - 1].rank;
    if (!same) t.events.push_back(locals[i].time);
    merged[locals[i].part][locals[i].k] = static_cast<int>(t.events.size()) - 1;
  }
  const int g = static_cast<int>(t.events.size()) - 1;
  t.goal_event = g;
  t.horizon = g;
  const std::size_t na = d.automata.size();
  t.locations.assign(na, std::vector<int>(g + 1, 0));
  t.commands.assign(na, std::vector<int>(g + 1, 0));
  for (std::size_t p = 0; p < parts.size(); ++p) {
    const Trajectory& lp = plans[p];
    for (std::size_t j = 0; j < parts[p].automata.size(); ++j) {
      int a = parts[p].automata[j];
      int local = 0;  // the part's stage in force at each merged stage
      for (int s = 0; s <= g; ++s) {
        while (local + 1 < static_cast<int>(lp.events.size()) && merged[p][local + 1] <= s) ++local;
        t.locations[a][s] = lp.locations[j][local];
      }
    }
    for (const auto& f : lp.fired) {
      int a = parts[p].automata[f.automaton];
      int ge = merged[p][f.event];
      t.fired.push_back({ge, a, f.transition});
      t.commands[a][ge - 1] = lp.commands[f.automaton][f.event - 1];
    }
  }
  std::sort(t.fired.begin(), t.fired.end(), [](const FiredTransition& x, const FiredTransition& y) {
    return x.event != y.event ? x.event < y.event : x.automaton < y.automaton;
  });
  t.episodes.assign(sp.episodes.size(), {0, 0});
  t.temporals.assign(sp.temporals.size(), {0, 0});
  for (std::size_t p = 0; p < parts.size(); ++p) {
    for (std::size_t e = 0; e < parts[p].episode_map.size(); ++e)
      t.episodes[parts[p].episode_map[e]] = {merged[p][plans[p].episodes[e].first],
                                             merged[p][plans[p].episodes[e].second]};
    for (std::size_t q = 0; q < parts[p].temporal_map.size(); ++q)
      t.temporals[parts[p].temporal_map[q]] = {merged[p][plans[p].temporals[q].first],
                                               merged[p][plans[p].temporals[q].second]};
  }
  return t;
}

}  // namespace ctb
