#include "planner/analyze/turns.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "planner/expr/normalize.h"

namespace ctb {

namespace {
namespace turn_taking {  // (unity builds: workload.cpp has a Job, time_network.cpp a Node)

using Node = std::pair<int, int>;  // (automaton, location)
constexpr long kNeverTurn = EarliestTimes::kNever;
constexpr std::size_t kMaxTurnNodes = 512;  // locations taken into account, at most
constexpr std::size_t kMaxCliqueStarts = 64;
constexpr std::size_t kMaxTailSplits = 128;  // jobs on a clique for which every tail Q is tried
constexpr std::size_t kMaxPool = 10;          // jobs in a pool of at most k at once

long AddTurn(long a, long b) { return std::min(kNeverTurn, a + b); }

// A location atom on the stage itself, under any number of `not`: its node and whether it says
// the automaton is there.
bool StageLiteral(const Expr& e, Node& node, bool& there) {
  const Expr* x = &e;
  bool flip = false;
  while (x->op == Expr::Op::kNot) x = &x->kids[0], flip = !flip;
  if (x->op != Expr::Op::kAtom || x->var_kind != VarKind::kLocation || x->index.kind != IndexKind::kI)
    return false;
  node = {x->target, x->value_code};
  there = !x->not_equal != flip;
  return true;
}

// The two locations a conjunct keeps from being occupied on one stage, when it has one of the
// forms `not (A /\ B)`, `not A \/ not B` or `A -> not B` (A, B: "automaton at location").
std::optional<std::pair<Node, Node>> Exclusion(const Expr& e) {
  Node a, b;
  bool ta = false, tb = false;
  auto two = [&](const Expr& x, const Expr& y, bool want_a, bool want_b) {
    return StageLiteral(x, a, ta) && StageLiteral(y, b, tb) && ta == want_a && tb == want_b &&
           a.first != b.first;
  };
  bool ok = false;
  if (e.op == Expr::Op::kNot && e.kids[0].op == Expr::Op::kAnd)
    ok = two(e.kids[0].kids[0], e.kids[0].kids[1], true, true);
  else if (e.op == Expr::Op::kOr)
    ok = two(e.kids[0], e.kids[1], false, false);
  else if (e.op == Expr::Op::kImplies)
    ok = two(e.kids[0], e.kids[1], true, false);
  if (!ok) return std::nullopt;
  return std::make_pair(a, b);
}

// The locations a conjunct keeps from being all occupied on one stage, when it has the form
// `not (A1 /\ ... /\ Am)` or `not A1 \/ ... \/ not Am` with m >= 3 literals "automaton at
// location" of distinct automata: at most m - 1 of them at once. Sorted.
std::optional<std::vector<Node>> NotAll(const Expr& e) {
  std::vector<const Expr*> lits;
  bool want = true;
  if (e.op == Expr::Op::kNot && e.kids[0].op == Expr::Op::kAnd) {
    Flatten(e.kids[0], Expr::Op::kAnd, lits);
  } else if (e.op == Expr::Op::kOr) {
    Flatten(e, Expr::Op::kOr, lits);
    want = false;
  } else {
    return std::nullopt;
  }
  if (lits.size() < 3) return std::nullopt;
  std::vector<Node> out;
  std::set<int> automata;
  for (const Expr* x : lits) {
    Node n;
    bool there = false;
    if (!StageLiteral(*x, n, there) || there != want || !automata.insert(n.first).second)
      return std::nullopt;
    out.push_back(n);
  }
  std::sort(out.begin(), out.end());
  return out;
}

struct Job {
  long r = 0, p = 0, q = 0;
};

// k machines (at most k of the locations at once): goal >= r + p + q of each job, and
// goal >= R + ceil(sum p / k) + Q over any set of jobs released at R or later with tails of at
// least Q (their work fits between R and goal - Q on k machines). The best such set for each
// least tail Q is a prefix of the jobs with q >= Q taken by release, latest first. Q is every
// job's tail, or, beyond kMaxTailSplits jobs, the least one (all the jobs). One machine (k = 1)
// is the preemptive bound: goal >= min r + sum p + min q.
long PoolBound(std::vector<Job> jobs, long k) {
  long best = 0;
  for (const Job& j : jobs) best = std::max(best, AddTurn(AddTurn(j.r, j.p), j.q));
  std::sort(jobs.begin(), jobs.end(), [](const Job& x, const Job& y) { return x.r > y.r; });
  std::vector<long> tails;
  if (jobs.size() <= kMaxTailSplits)
    for (const Job& j : jobs) tails.push_back(j.q);
  else
    tails.push_back(std::min_element(jobs.begin(), jobs.end(),
                                     [](const Job& x, const Job& y) { return x.q < y.q; })->q);
  for (long tail : tails) {
    long sum = 0;
    for (const Job& j : jobs) {
      if (j.q < tail) continue;
      sum = AddTurn(sum, j.p);
      best = std::max(best, AddTurn(AddTurn(j.r, (sum + k - 1) / k), tail));
    }
  }
  return best;
}

// With few jobs, the exact optimum of one machine without preemption (each visit is one stay):
// every order, each job as early as its release and the previous job allow.
constexpr std::size_t kMaxExactJobs = 8;

long BestOrder(const std::vector<Job>& jobs) {
  std::vector<std::size_t> order(jobs.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  long best = kNeverTurn;
  do {
    long free = 0, end = 0;
    for (std::size_t k : order) {
      free = AddTurn(std::max(free, jobs[k].r), jobs[k].p);
      end = std::max(end, AddTurn(free, jobs[k].q));
      if (end >= best) break;
    }
    best = std::min(best, end);
  } while (std::next_permutation(order.begin(), order.end()));
  return best;
}

long MachineBound(const std::vector<Job>& jobs) {
  const long preemptive = PoolBound(jobs, 1);
  return jobs.size() <= kMaxExactJobs ? std::max(preemptive, BestOrder(jobs)) : preemptive;
}

class Turns {
 public:
  Turns(const Domain& d, const StatePlan& sp, const EarliestTimes* ticks)
      : d_(d), sp_(sp), ticks_(ticks), tps_(std::max(1L, std::lround(1.0 / d.time_resolution))) {}

  TurnBound Run() {
    TurnBound out;
    if (sp_.goal.info.IsChange()) return out;
    goal_.assign(d_.automata.size(), -1);
    std::vector<std::pair<int, int>> pins;
    RequiredLocations(sp_.goal.expr, pins);
    for (auto [a, loc] : pins) goal_[a] = loc;
    CollectJobs();
    if (jobs_.size() < 2) return out;
    for (const auto& clique : Cliques()) {
      std::vector<Job> on;
      for (const Node& n : clique) on.push_back(jobs_.at(n));
      ++out.machines;
      const long b = MachineBound(on);
      if (b > out.makespan_ticks) out.makespan_ticks = b, out.jobs = static_cast<int>(on.size());
    }
    for (const auto& [k, pool] : Pools()) {
      std::vector<Job> on;
      for (const Node& n : pool) on.push_back(jobs_.at(n));
      ++out.machines;
      const long b = PoolBound(on, k);
      if (b > out.makespan_ticks) out.makespan_ticks = b, out.jobs = static_cast<int>(on.size());
    }
    return out;
  }

 private:
  long Ticks(const Transition& t) const { return std::lround(t.duration.lo * static_cast<double>(tps_)); }

  // The exclusions of the maintenance constraint whose both ends are jobs with some duration.
  void CollectJobs() {
    std::vector<const Expr*> parts;
    Flatten(sp_.maintenance.expr, Expr::Op::kAnd, parts);
    for (const Expr* part : parts) {
      if (auto all = NotAll(*part)) {
        if (std::all_of(all->begin(), all->end(), [&](const Node& n) { return IsJob(n); }))
          groups_[static_cast<long>(all->size()) - 1].insert(*all);
        continue;
      }
      auto ex = Exclusion(*part);
      if (!ex || !IsJob(ex->first) || !IsJob(ex->second)) continue;
      edges_.insert(*ex);
      edges_.insert({ex->second, ex->first});
    }
  }

  // Pools of jobs of which at most k run at once: sets in which every k + 1 jobs are a group
  // the maintenance constraint excludes (`NotAll`), grown greedily from each group, longest jobs
  // first, to at most kMaxPool jobs.
  std::vector<std::pair<long, std::vector<Node>>> Pools() const {
    std::vector<std::pair<long, std::vector<Node>>> out;
    for (const auto& [k, groups] : groups_) {
      std::set<Node> nodes;
      for (const auto& g : groups) nodes.insert(g.begin(), g.end());
      std::vector<Node> by_length(nodes.begin(), nodes.end());
      std::sort(by_length.begin(), by_length.end(),
                [&](const Node& x, const Node& y) { return jobs_.at(x).p > jobs_.at(y).p; });
      std::size_t starts = 0;
      for (const auto& g : groups) {
        if (++starts > kMaxCliqueStarts) break;
        std::vector<Node> pool = g;
        for (const Node& n : by_length)
          if (pool.size() < kMaxPool && std::find(pool.begin(), pool.end(), n) == pool.end() &&
              Joins(pool, n, k, groups))
            pool.push_back(n);
        out.emplace_back(k, std::move(pool));
      }
    }
    return out;
  }

  // Whether every k jobs of `pool` with n make an excluded group.
  static bool Joins(const std::vector<Node>& pool, const Node& n, long k,
                    const std::set<std::vector<Node>>& groups) {
    std::vector<bool> pick(pool.size(), false);
    std::fill(pick.begin(), pick.begin() + k, true);
    do {
      std::vector<Node> g = {n};
      for (std::size_t i = 0; i < pool.size(); ++i)
        if (pick[i]) g.push_back(pool[i]);
      std::sort(g.begin(), g.end());
      if (!groups.count(g)) return false;
    } while (std::prev_permutation(pick.begin(), pick.end()));
    return true;
  }

  bool IsJob(const Node& n) {
    if (auto it = jobs_.find(n); it != jobs_.end()) return true;
    if (not_jobs_.count(n) || jobs_.size() >= kMaxTurnNodes) return false;
    auto job = JobOf(n.first, n.second);
    if (!job || job->p <= 0) {
      not_jobs_.insert(n);
      return false;
    }
    jobs_[n] = *job;
    return true;
  }

  // Automaton a must visit l (see turns.h), with its release, least stay and least tail.
  std::optional<Job> JobOf(int a, int l) {
    const Automaton& A = d_.automata[a];
    const int g = goal_[a], start = sp_.initial[a];
    if (g < 0 || g == l || start == l || Reaches(A, start, g, l)) return std::nullopt;
    Job j;
    j.r = ticks_ ? ticks_->arrival[a][l] : 0;
    j.p = j.q = kNeverTurn;
    for (const Transition& t : A.transitions) {
      if (t.from != l || t.to == l) continue;
      j.p = std::min(j.p, Ticks(t));
      j.q = std::min(j.q, ShortestFrom(A, t.to, [this](const Transition& x) { return Ticks(x); })[g]);
    }
    if (j.r >= kNeverTurn || j.p >= kNeverTurn || j.q >= kNeverTurn) return std::nullopt;
    return j;
  }

  // True when a path from `from` to `to` avoids location `avoid`.
  static bool Reaches(const Automaton& A, int from, int to, int avoid) {
    std::vector<bool> seen(A.locations.size(), false);
    std::vector<int> stack = {from};
    seen[from] = true;
    while (!stack.empty()) {
      const int l = stack.back();
      stack.pop_back();
      if (l == to) return true;
      for (const Transition& t : A.transitions)
        if (t.from == l && t.to != avoid && !seen[t.to]) seen[t.to] = true, stack.push_back(t.to);
    }
    return false;
  }

  bool Exclusive(const Node& x, const Node& y) const {
    return x.first == y.first ? x.second != y.second : edges_.count({x, y}) > 0;
  }

  // Greedy cliques of mutually exclusive jobs, one from each of the longest jobs.
  std::vector<std::vector<Node>> Cliques() const {
    std::vector<Node> nodes;
    for (const auto& [n, j] : jobs_)
      if (std::any_of(edges_.begin(), edges_.end(), [&](const auto& e) { return e.first == n; }))
        nodes.push_back(n);
    std::sort(nodes.begin(), nodes.end(),
              [&](const Node& x, const Node& y) { return jobs_.at(x).p > jobs_.at(y).p; });
    std::vector<std::vector<Node>> out;
    for (std::size_t s = 0; s < nodes.size() && s < kMaxCliqueStarts; ++s) {
      std::vector<Node> clique = {nodes[s]};
      for (const Node& n : nodes)
        if (n != nodes[s] && std::all_of(clique.begin(), clique.end(),
                                         [&](const Node& m) { return Exclusive(n, m); }))
          clique.push_back(n);
      if (clique.size() >= 2) out.push_back(std::move(clique));
    }
    return out;
  }

  const Domain& d_;
  const StatePlan& sp_;
  const EarliestTimes* ticks_;
  const long tps_;
  std::vector<int> goal_;
  std::map<Node, Job> jobs_;
  std::set<Node> not_jobs_;
  std::set<std::pair<Node, Node>> edges_;
  std::map<long, std::set<std::vector<Node>>> groups_;  // k -> groups of k + 1 excluded at once
};

}  // namespace turn_taking
}  // namespace

TurnBound ComputeTurnBound(const Domain& d, const StatePlan& sp, const EarliestTimes* ticks) {
  return turn_taking::Turns(d, sp, ticks).Run();
}

}  // namespace ctb
