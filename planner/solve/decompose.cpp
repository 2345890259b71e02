#include "planner/solve/decompose.h"

#include <algorithm>
#include <map>
#include <numeric>

#include "planner/expr/expr_print.h"

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

// What a sub-tree reads.
void Reads(const Expr& e, ExprInfo& info) {
  if (e.op == Expr::Op::kAtom) {
    switch (e.var_kind) {
      case VarKind::kLocation: info.locations_read.insert(e.target); break;
      case VarKind::kCommand: info.commands_read.insert(e.target); break;
      case VarKind::kEpisodeState: info.episodes_read.insert(e.target); break;
      case VarKind::kTemporalState: info.temporals_read.insert(e.target); break;
      default: break;
    }
  }
  for (const auto& k : e.kids) Reads(k, info);
}

}  // namespace

std::vector<SubProblem> SplitProblem(const Domain& d, const StatePlan& sp) {
  if (sp.maintenance.expr.op != Expr::Op::kTrue) return {};
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
    ExprInfo info;
    Reads(*goal[c], info);
    link(gc(c), info);
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
  const Json dj = DomainToJson(d), spj = StatePlanToJson(sp, d);
  for (std::size_t k = 0; k < parts.size(); ++k) {
    SubProblem& sub = parts[k];
    sub.automata = automata[k];
    Json sdj = dj;
    sdj["name"] = d.name + "_part" + std::to_string(k + 1);
    sdj["automata"] = Json::array();
    Json init = Json::object();
    for (int a : sub.automata) {
      sdj["automata"].push_back(dj["automata"][a]);
      init[d.automata[a].name] = d.automata[a].locations[sp.initial[a]];
    }
    std::string goal_text;
    for (int c = 0; c < ng; ++c)
      if (part(gc(c)) == static_cast<int>(k))
        goal_text += (goal_text.empty() ? "" : " /\\ ") + PrintSource(*goal[c]);
    Json eps = Json::object(), tcs = Json::object(), evs = Json::object();
    for (int p = 0; p < ne; ++p)
      if (part(ep(p)) == static_cast<int>(k))
        eps[sp.episodes[p].name] = spj["constraints"]["episodes"][sp.episodes[p].name];
    for (int q = 0; q < nq; ++q)
      if (part(tc(q)) == static_cast<int>(k))
        tcs[sp.temporals[q].name] = spj["constraints"]["temporal"][sp.temporals[q].name];
    for (const auto& ev : sp.events) {
      const Endpoint& e0 = ev.endpoints[0];
      int node = e0.kind == EndpointKind::kEpisodeStart || e0.kind == EndpointKind::kEpisodeEnd
                     ? ep(e0.index) : tc(e0.index);
      if (part(node) == static_cast<int>(k)) evs[ev.name] = spj["constraints"]["event"][ev.name];
    }
    Json sspj = {{"initial_state", init},
                 {"end_state", {{"maintenance_constraint", "true"},
                                {"goal_constraint", goal_text.empty() ? "true" : goal_text}}},
                 {"constraints", {{"episodes", eps}, {"temporal", tcs}, {"event", evs}}},
                 {"objective", ObjectiveName(sp.objective)}};
    Diagnostics diags;
    auto sd = LoadDomain(sdj, diags);
    if (!sd) return {};
    auto ssp = LoadStatePlan(sspj, *sd, diags);
    if (!ssp) return {};
    sub.domain = std::move(*sd);
    sub.plan = std::move(*ssp);
    for (const auto& e : sub.plan.episodes)
      for (int p = 0; p < ne; ++p)
        if (sp.episodes[p].name == e.name) sub.episode_map.push_back(p);
    for (const auto& t : sub.plan.temporals)
      for (int q = 0; q < nq; ++q)
        if (sp.temporals[q].name == t.name) sub.temporal_map.push_back(q);
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
