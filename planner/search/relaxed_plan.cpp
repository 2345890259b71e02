#include "planner/search/relaxed_plan.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>

namespace ctb::search {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr std::size_t kMaxAlternatives = 256;

using Atoms = std::vector<std::pair<int, int>>;  // (automaton, location)

// The alternatives of a guard as the positive location atoms each needs (a disjunctive normal
// form keeping only those atoms). Beyond kMaxAlternatives, one empty alternative: needing less is
// still a relaxation. The same reading as planner/analyze/relaxed_cost.cpp.
std::vector<Atoms> Alternatives(const Expr& e) {
  switch (e.op) {
    case Expr::Op::kFalse: return {};
    case Expr::Op::kAtom:
      if (e.var_kind == VarKind::kLocation && !e.not_equal && e.index.kind != IndexKind::kFixed)
        return {{{e.target, e.value_code}}};
      return {{}};
    case Expr::Op::kOr: {
      auto out = Alternatives(e.kids[0]);
      auto more = Alternatives(e.kids[1]);
      out.insert(out.end(), more.begin(), more.end());
      if (out.size() > kMaxAlternatives) return {{}};
      return out;
    }
    case Expr::Op::kAnd: {
      std::vector<Atoms> out;
      for (const Atoms& x : Alternatives(e.kids[0]))
        for (const Atoms& y : Alternatives(e.kids[1])) {
          Atoms both = x;
          both.insert(both.end(), y.begin(), y.end());
          out.push_back(std::move(both));
          if (out.size() > kMaxAlternatives) return {{}};
        }
      return out;
    }
    default: return {{}};
  }
}

// The top-level conjuncts of e that are "automaton != location" atoms.
void RefusedAtoms(const Expr& e, std::vector<Atoms>& out) {
  if (e.op == Expr::Op::kAnd) {
    for (const Expr& k : e.kids) RefusedAtoms(k, out);
  } else if (e.op == Expr::Op::kAtom && e.var_kind == VarKind::kLocation && e.not_equal &&
             e.index.kind != IndexKind::kFixed) {
    out[0].emplace_back(e.target, e.value_code);
  }
}

}  // namespace

RelaxedPlan::RelaxedPlan(const Domain& d, const StatePlan& sp, Objective objective,
                         long ticks_per_second)
    : d_(d), sp_(sp), objective_(objective), tps_(ticks_per_second) {
  for (const auto& a : d.automata) {
    offset_.push_back(facts_);
    facts_ += static_cast<int>(a.locations.size());
  }
  pre_of_.resize(facts_);
  out_of_.resize(facts_);
  stays_.resize(d.automata.size());
  // The events transitions fire on together: a union of each commanded transition with the
  // transitions on the commands its guard requires of other automata.
  std::vector<int> first(d.automata.size() + 1, 0);
  for (std::size_t a = 0; a < d.automata.size(); ++a)
    first[a + 1] = first[a] + static_cast<int>(d.automata[a].transitions.size());
  std::vector<int> parent(first.back());
  for (int i = 0; i < first.back(); ++i) parent[i] = i;
  std::function<int(int)> root = [&](int i) { return parent[i] == i ? i : parent[i] = root(parent[i]); };
  for (std::size_t a = 0; a < d.automata.size(); ++a) {
    const auto& trs = d.automata[a].transitions;
    for (std::size_t ti = 0; ti < trs.size(); ++ti) {
      const Transition& tr = trs[ti];
      if (!tr.commanded || tr.command <= 0) continue;
      for (int b : tr.guard_info.commands_read) {
        const int want = RequiredCommand(tr.guard, b);
        if (want <= 0 || b == static_cast<int>(a)) continue;
        const auto& other = d.automata[b].transitions;
        for (std::size_t tj = 0; tj < other.size(); ++tj)
          if (other[tj].commanded && other[tj].command == want)
            parent[root(first[a] + static_cast<int>(ti))] = root(first[b] + static_cast<int>(tj));
      }
    }
  }
  std::vector<int> numbered(first.back(), -1), group_of(first.back());
  for (int i = 0; i < first.back(); ++i) {
    int& g = numbered[root(i)];
    if (g < 0) g = groups_++;
    group_of[i] = g;
  }
  for (std::size_t a = 0; a < d.automata.size(); ++a) {
    const auto& trs = d.automata[a].transitions;
    for (std::size_t ti = 0; ti < trs.size(); ++ti) {
      const Transition& tr = trs[ti];
      const long lo = std::lround(tr.duration.lo * static_cast<double>(tps_));
      const double base = objective == Objective::kMakespan
                              ? static_cast<double>(lo) + 0.01
                              : static_cast<double>(tr.cost) + 1e-6 * static_cast<double>(lo);
      for (const Atoms& alt : Alternatives(tr.guard)) {
        Action act;
        act.pre.push_back(Fact(static_cast<int>(a), tr.from));
        for (auto [b, l] : alt) {
          const int f = Fact(b, l);
          if (std::find(act.pre.begin(), act.pre.end(), f) == act.pre.end()) act.pre.push_back(f);
        }
        act.add = Fact(static_cast<int>(a), tr.to);
        act.automaton = static_cast<int>(a);
        act.transition = static_cast<int>(ti);
        act.cost = base;
        act.lo = lo;
        act.choosable = (tr.commanded && tr.command > 0) || (!tr.commanded && tr.controllable);
        act.group = group_of[first[a] + static_cast<int>(ti)];
        if (tr.duration.hi) act.hi = std::lround(*tr.duration.hi * static_cast<double>(tps_));
        for (int f : act.pre) pre_of_[f].push_back(static_cast<int>(actions_.size()));
        out_of_[act.pre[0]].push_back(static_cast<int>(actions_.size()));
        stays_[a].push_back(static_cast<int>(actions_.size()));
        actions_.push_back(std::move(act));
      }
    }
  }
  auto need = [](const Condition& c) { return Need{ToClauses(c.expr), !c.info.IsChange()}; };
  goal_ = need(sp.goal);
  std::vector<Atoms> refused(1);
  RefusedAtoms(sp.goal.expr, refused);
  refused_.resize(d.automata.size());
  for (auto [a, l] : refused[0]) {
    if (refused_[a].empty()) refused_[a].assign(d.automata[a].locations.size(), 0);
    refused_[a][l] = 1;
  }
  for (const auto& ep : sp.episodes) ep_acc_.push_back(need(ep.accepting));
  for (const auto& tc : sp.temporals) {
    tc_ev1_.push_back(need(tc.event1));
    tc_ev2_.push_back(need(tc.event2));
  }
}

double RelaxedPlan::ActionCost(const Action& act, const Node& n) const {
  const int a = act.automaton;
  if (act.pre[0] != Fact(a, n.loc[a]) || act.lo == 0) return act.cost;
  // The first transition out of the current location: the clock has already run.
  const long spent = std::min(act.lo, n.time - n.entry[a]);
  return act.cost - (objective_ == Objective::kMakespan ? 1.0 : 1e-6) * static_cast<double>(spent);
}

void RelaxedPlan::Needed(const Node& n, std::vector<const Need*>& needed, double& wait) const {
  needed.push_back(&goal_);
  const Monitors& m = n.mon;
  wait = 0;
  for (std::size_t p = 0; p < sp_.episodes.size(); ++p) {
    if (m.ep_start[p] < 0)
      needed.push_back(&ep_acc_[p]);
    else if (m.ep_end[p] < 0)
      wait = std::max(wait, static_cast<double>(m.ep_start_t[p] +
                                                std::lround(sp_.episodes[p].lower * tps_) - n.time));
  }
  for (std::size_t q = 0; q < sp_.temporals.size(); ++q) {
    if (m.tc_k1[q] < 0)
      needed.push_back(&tc_ev1_[q]);
    if (m.tc_k2[q] < 0)
      needed.push_back(&tc_ev2_[q]);
    if ((m.tc_k1[q] < 0) != (m.tc_k2[q] < 0))
      wait = std::max(wait, static_cast<double>(m.tc_first_t[q] +
                                                std::lround(sp_.temporals[q].lower * tps_) - n.time));
  }
}

bool RelaxedPlan::Targets(const Node& n, const std::vector<double>& cost, std::vector<int>& facts,
                          double& wait) const {
  std::vector<const Need*> needed;
  Needed(n, needed, wait);
  std::vector<char> chosen(facts_, 0);
  auto cost_of = [&](const LocationAtom& t) {
    const int f = Fact(t.first, t.second);
    return chosen[f] ? 0.0 : cost[f];
  };
  std::vector<LocationAtom> picked;
  for (const Need* c : needed) {
    picked.clear();
    if (!ChooseFacts(c->clauses, c->one_stage, cost_of, picked)) return false;
    for (const LocationAtom& t : picked) {
      const int f = Fact(t.first, t.second);
      facts.push_back(f);  // again when chosen before: the extraction skips it
      chosen[f] = 1;
    }
    if (c != &goal_) continue;
    // An automaton where the goal refuses it: the cheapest location the goal allows, unless the
    // goal's clauses already chose an allowed one.
    for (std::size_t a = 0; a < refused_.size(); ++a) {
      const auto& no = refused_[a];
      if (no.empty() || !no[n.loc[a]]) continue;
      bool settled = false;
      for (const LocationAtom& t : picked) settled = settled || (t.first == static_cast<int>(a) && !no[t.second]);
      if (settled) continue;
      int best = -1;
      for (std::size_t l = 0; l < no.size(); ++l) {
        const int f = Fact(static_cast<int>(a), static_cast<int>(l));
        if (!no[l] && !std::isinf(cost[f]) && (best < 0 || cost[f] < cost[best])) best = f;
      }
      if (best < 0) return false;
      facts.push_back(best);
      chosen[best] = 1;
    }
  }
  return true;
}

Estimate RelaxedPlan::Evaluate(const Node& n) const {
  Estimate est;
  std::vector<double> cost(facts_, kInf);
  std::vector<int> support(facts_, -1);
  std::vector<int> unsat(actions_.size());
  for (std::size_t i = 0; i < actions_.size(); ++i) unsat[i] = static_cast<int>(actions_[i].pre.size());
  // An automaton whose every way out has closed stays where it is: its actions never apply.
  for (std::size_t a = 0; a < d_.automata.size(); ++a) {
    const auto& out = out_of_[Fact(static_cast<int>(a), n.loc[a])];
    if (out.empty()) continue;
    const long clock = n.time - n.entry[a];
    bool closed = true;
    for (int ai : out) closed = closed && actions_[ai].hi >= 0 && clock > actions_[ai].hi;
    if (closed)
      for (int ai : stays_[a]) unsat[ai] = -1;
  }
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  std::vector<char> settled(facts_, 0);
  for (std::size_t a = 0; a < d_.automata.size(); ++a) {
    const int f = Fact(static_cast<int>(a), n.loc[a]);
    cost[f] = 0;
    queue.emplace(0.0, f);
  }
  // h_add by a generalised Dijkstra: an action's cost is its own plus its preconditions'.
  while (!queue.empty()) {
    auto [c, f] = queue.top();
    queue.pop();
    if (settled[f]) continue;
    settled[f] = 1;
    for (int ai : pre_of_[f]) {
      if (--unsat[ai] != 0) continue;
      const Action& act = actions_[ai];
      double sum = ActionCost(act, n);
      for (int p : act.pre) sum += cost[p];
      if (sum < cost[act.add]) {
        cost[act.add] = sum;
        support[act.add] = ai;
        queue.emplace(sum, act.add);
      }
    }
  }
  std::vector<int> stack;
  double wait = 0;
  if (!Targets(n, cost, stack, wait)) {
    est.dead = true;
    return est;
  }
  // The relaxed plan: the best supporters of every needed fact, each action counted once.
  std::vector<char> marked(actions_.size(), 0), seen(facts_, 0);
  double h = 0;
  // Makespan: each event of the relaxed plan once, at its longest transition.
  std::vector<std::pair<int, double>> events;
  while (!stack.empty()) {
    const int f = stack.back();
    stack.pop_back();
    if (seen[f] || cost[f] == 0) continue;
    seen[f] = 1;
    const int ai = support[f];
    if (marked[ai]) continue;
    marked[ai] = 1;
    const Action& act = actions_[ai];
    if (objective_ == Objective::kMakespan)
      events.emplace_back(act.group, ActionCost(act, n));
    else
      h += ActionCost(act, n);
    bool now = true;
    for (int p : act.pre) {
      stack.push_back(p);
      now = now && cost[p] == 0;
    }
    if (now && act.choosable) est.helpful.emplace_back(act.automaton, act.transition);
  }
  std::sort(events.begin(), events.end());
  for (std::size_t i = 0; i < events.size(); ++i)
    if (i + 1 == events.size() || events[i + 1].first != events[i].first) h += events[i].second;
  est.h = h + (objective_ == Objective::kMakespan ? 1.0 : 1e-6) * wait;
  return est;
}

}  // namespace ctb::search
