#include "planner/analyze/abstraction.h"

#include <functional>
#include <queue>
#include <utility>

#include "planner/expr/normalize.h"

namespace ctb::analysis {

namespace {

// `stage_opts` is left as it was; it is changed during the call (not copied per transition).
bool GuardMayHold(const Transition& tr, int self, const std::vector<int>& init,
                  std::vector<std::vector<Opt>>& stage_opts) {
  if (IsTrue(tr.guard)) return true;
  // The own automaton is in `from`: pin it by giving it that single option.
  std::vector<Opt> own{Opt{tr.from, tr.from}};
  std::swap(stage_opts[self], own);
  std::vector<Term> terms{{&tr.guard, false}};
  SatSearch s(init, stage_opts, terms);
  const bool may = s.Run();
  std::swap(stage_opts[self], own);
  return may;
}

// Least total weight between every two nodes, [from * n + to] (kInf: none), by Dijkstra from
// each node: the graphs are sparse, and Floyd-Warshall's n^3 took seconds on automata with a
// location per robot (64 robots).
std::vector<double> AllPairsLeast(const std::vector<std::vector<std::pair<int, double>>>& edges) {
  const int n = static_cast<int>(edges.size());
  std::vector<double> dist(static_cast<std::size_t>(n) * n, kInf);
  using Item = std::pair<double, int>;
  for (int s = 0; s < n; ++s) {
    double* row = &dist[static_cast<std::size_t>(s) * n];
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
    row[s] = 0;
    open.push({0, s});
    while (!open.empty()) {
      auto [d, u] = open.top();
      open.pop();
      if (d > row[u]) continue;
      for (auto [v, w] : edges[u])
        if (d + w < row[v]) {
          row[v] = d + w;
          open.push({row[v], v});
        }
    }
  }
  return dist;
}

}  // namespace

std::vector<std::vector<Opt>> StageOpts(const std::vector<std::vector<char>>& reach) {
  std::vector<std::vector<Opt>> out(reach.size());
  for (std::size_t a = 0; a < reach.size(); ++a)
    for (std::size_t l = 0; l < reach[a].size(); ++l)
      if (reach[a][l]) out[a].push_back({static_cast<int>(l), static_cast<int>(l)});
  return out;
}

// allowed[a][l]: the locations the maintenance constraint admits (all when none).
Abstraction Build(const Domain& d, const StatePlan& sp,
                  const std::vector<std::vector<char>>* allowed) {
  Abstraction ab;
  ab.d = &d;
  ab.init = sp.initial;
  const std::size_t na = d.automata.size();
  ab.reach.resize(na);
  ab.usable.resize(na);
  for (std::size_t a = 0; a < na; ++a) {
    ab.reach[a].assign(d.automata[a].locations.size(), 0);
    ab.usable[a].assign(d.automata[a].transitions.size(), 0);
    if (allowed && !(*allowed)[a][sp.initial[a]]) ab.only_initial = true;
  }
  for (std::size_t a = 0; a < na; ++a) ab.reach[a][sp.initial[a]] = 1;
  if (!ab.only_initial) {
    // Stages before the goal event: within the allowed locations.
    for (bool changed = true; changed;) {
      changed = false;
      auto stage = StageOpts(ab.reach);
      for (std::size_t a = 0; a < na; ++a) {
        const Automaton& au = d.automata[a];
        for (std::size_t t = 0; t < au.transitions.size(); ++t) {
          const Transition& tr = au.transitions[t];
          if (ab.usable[a][t] || !ab.reach[a][tr.from]) continue;
          if (allowed && !(*allowed)[a][tr.to]) continue;
          if (!GuardMayHold(tr, static_cast<int>(a), ab.init, stage)) continue;
          ab.usable[a][t] = 1;
          if (!ab.reach[a][tr.to]) changed = true;
          ab.reach[a][tr.to] = 1;
        }
      }
    }
    // The goal event may lead out of the allowed locations, by one transition.
    if (allowed) {
      auto stage = StageOpts(ab.reach);
      auto final_reach = ab.reach;
      for (std::size_t a = 0; a < na; ++a) {
        const Automaton& au = d.automata[a];
        for (std::size_t t = 0; t < au.transitions.size(); ++t) {
          const Transition& tr = au.transitions[t];
          if (ab.usable[a][t] || !ab.reach[a][tr.from]) continue;
          if (!GuardMayHold(tr, static_cast<int>(a), ab.init, stage)) continue;
          ab.usable[a][t] = 1;
          final_reach[a][tr.to] = 1;
        }
      }
      ab.reach = final_reach;
    }
  }
  ab.stage_opts = StageOpts(ab.reach);
  ab.event_opts.resize(na);
  ab.dist.resize(na);
  for (std::size_t a = 0; a < na; ++a) {
    const Automaton& au = d.automata[a];
    const int n = static_cast<int>(au.locations.size());
    ab.event_guards.emplace_back();
    for (int l = 0; l < n; ++l)
      if (ab.reach[a][l] && !(ab.only_initial && l != sp.initial[a])) {
        ab.event_opts[a].push_back({l, l});
        ab.event_guards[a].push_back(nullptr);
      }
    std::vector<std::vector<std::pair<int, double>>> edges(n);
    for (std::size_t t = 0; t < au.transitions.size(); ++t) {
      if (!ab.usable[a][t]) continue;
      const Transition& tr = au.transitions[t];
      ab.event_opts[a].push_back({tr.from, tr.to});
      ab.event_guards[a].push_back(tr.from == tr.to || IsTrue(tr.guard) ? nullptr : &tr.guard);
      edges[tr.from].emplace_back(tr.to, tr.duration.lo);
    }
    ab.dist[a] = AllPairsLeast(edges);
  }
  return ab;
}

// Whether the terms can hold together at one event of the abstraction.
bool MayHold(const Abstraction& ab, const std::vector<Term>& terms) {
  bool change = false;
  for (const auto& t : terms) change = change || t.change;
  if (change && ab.only_initial) return false;  // a change needs an event after e[0]
  SatSearch s(ab.init, change ? ab.event_opts : ab.stage_opts, terms);
  return s.Run();
}

// For each automaton, the options (at one event) compatible with the terms; automata the terms
// do not read keep every option.
std::vector<std::vector<Opt>> Project(const Abstraction& ab, const std::vector<Term>& terms,
                                      bool guards) {
  std::vector<std::vector<Opt>> out = ab.event_opts;
  SatSearch s(ab.init, ab.event_opts, terms, guards ? &ab.event_guards : nullptr);
  for (int a : s.order()) {
    std::vector<Opt> keep;
    for (int o = 0; o < static_cast<int>(ab.event_opts[a].size()); ++o)
      if (s.Run(a, o)) keep.push_back(ab.event_opts[a][o]);
    out[a] = keep;
  }
  return out;
}

// Least time from an event at which `from` holds to a later event at which `to` holds.
double LeastGap(const Abstraction& ab, const std::vector<std::vector<Opt>>& from,
                const std::vector<std::vector<Opt>>& to) {
  double gap = 0;
  for (std::size_t a = 0; a < from.size(); ++a) {
    double best = kInf;
    for (const Opt& x : from[a])
      for (const Opt& y : to[a])
        best = std::min(best, ab.Gap(static_cast<int>(a), x.next, x.prev != x.next, y.next));
    gap = std::max(gap, best);
  }
  return gap;
}
}  // namespace ctb::analysis
