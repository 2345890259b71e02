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

struct Job {
  long r = 0, p = 0, q = 0;
};

// goal >= min r + sum p + min q over any set of jobs; the best such set for each least tail Q is
// a prefix of the jobs with q >= Q taken by release, latest first.
long OneMachineBound(std::vector<Job> jobs) {
  std::sort(jobs.begin(), jobs.end(), [](const Job& x, const Job& y) { return x.r > y.r; });
  std::vector<long> tails;
  if (jobs.size() <= kMaxTailSplits)
    for (const Job& j : jobs) tails.push_back(j.q);
  else
    tails.push_back(std::min_element(jobs.begin(), jobs.end(),
                                     [](const Job& x, const Job& y) { return x.q < y.q; })->q);
  long best = 0;
  for (long tail : tails) {
    long sum = 0;
    for (const Job& j : jobs) {
      if (j.q < tail) continue;
      sum = AddTurn(sum, j.p);
      best = std::max(best, AddTurn(AddTurn(j.r, sum), tail));
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
  const long preemptive = OneMachineBound(jobs);
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
    return out;
  }

 private:
  long Ticks(const Transition& t) const { return std::lround(t.duration.lo * static_cast<double>(tps_)); }

  // The exclusions of the maintenance constraint whose both ends are jobs with some duration.
  void CollectJobs() {
    std::vector<const Expr*> parts;
    Flatten(sp_.maintenance.expr, Expr::Op::kAnd, parts);
    for (const Expr* part : parts) {
      auto ex = Exclusion(*part);
      if (!ex || !IsJob(ex->first) || !IsJob(ex->second)) continue;
      edges_.insert(*ex);
      edges_.insert({ex->second, ex->first});
    }
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
};

}  // namespace turn_taking
}  // namespace

TurnBound ComputeTurnBound(const Domain& d, const StatePlan& sp, const EarliestTimes* ticks) {
  return turn_taking::Turns(d, sp, ticks).Run();
}

}  // namespace ctb
