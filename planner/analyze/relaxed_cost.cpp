#include "planner/analyze/relaxed_cost.h"

#include <algorithm>
#include <limits>
#include <set>
#include <utility>
#include <vector>

#include "planner/analyze/clauses.h"
#include "planner/analyze/earliest.h"  // RequiredLocations

namespace ctb {

namespace {

constexpr long kInf = std::numeric_limits<long>::max() / 4;
constexpr std::size_t kMaxAlternatives = 64;
// The work LM-cut may do (action visits of its passes, all rounds together, about 0.1 s): each
// round adds one cut, so a run stopped early has found a smaller bound that is still a bound.
// Robots that each need six transitions make six cuts a robot; 1,000 of them over 17,000
// actions took 2.3 s of every solve without the cap.
constexpr long kMaxLmCutWork = 40'000'000;

using Atoms = std::vector<std::pair<int, int>>;  // (automaton, location)

// The alternatives of e as sets of positive location atoms it needs (a disjunctive normal form
// that keeps only those atoms). Beyond kMaxAlternatives, one empty alternative: needing less is
// still a relaxation.
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

struct Action {
  std::vector<int> pre;
  int add = 0;
  long cost = 0;
};

// The relaxed task: facts are (automaton, location) pairs, then the goal fact, then one for the
// goal's alternatives and one per goal clause.
class RelaxedTask {
 public:
  // Transitions of the automata marked in `free_automata` cost 0; no action adds a fact of
  // `avoid`; with `clauses`, the goal is also read as clauses (AddGoal).
  RelaxedTask(const Domain& d, const StatePlan& sp, const std::vector<char>& free_automata = {},
              const std::vector<std::pair<int, int>>& avoid = {}, bool clauses = false) {
    const std::set<std::pair<int, int>> avoided(avoid.begin(), avoid.end());
    for (const auto& a : d.automata) {
      offset_.push_back(facts_);
      facts_ += static_cast<int>(a.locations.size());
    }
    goal_ = facts_++;
    for (std::size_t a = 0; a < d.automata.size(); ++a) {
      const bool free = a < free_automata.size() && free_automata[a];
      init_.push_back(Fact(static_cast<int>(a), sp.initial[a]));
      for (const Transition& t : d.automata[a].transitions) {
        if (avoided.count({static_cast<int>(a), t.to})) continue;
        for (const Atoms& alt : Alternatives(t.guard)) {
          Action act{{Fact(static_cast<int>(a), t.from)}, Fact(static_cast<int>(a), t.to),
                     free ? 0 : t.cost};
          for (auto [b, l] : alt) act.pre.push_back(Fact(b, l));
          actions_.push_back(std::move(act));
        }
      }
    }
    AddGoal(sp, clauses);
  }

  // True when h_max reaches the goal (a relaxed plan exists).
  bool Reachable() {
    std::vector<long> cost;
    for (const Action& a : actions_) cost.push_back(a.cost);
    return HMax(cost)[goal_] < kInf;
  }

  // LM-cut: repeatedly find a cut of actions every relaxed plan uses (from the h_max
  // justification graph), add its least cost, and subtract that from the cut's actions.
  std::optional<long> LmCut() {
    std::vector<long> cost;
    for (const Action& a : actions_) cost.push_back(a.cost);
    long h = 0;
    for (;;) {
      if (work_ > kMaxLmCutWork) return h;  // the cuts so far: a smaller bound, still a bound
      std::vector<long> hmax = HMax(cost);
      if (hmax[goal_] >= kInf) return std::nullopt;
      if (hmax[goal_] == 0) return h;
      std::vector<int> pcf = Supporters(hmax);
      std::vector<char> zone = GoalZone(pcf, cost);
      std::vector<char> before = BeforeZone(pcf, zone);
      long m = kInf;
      std::vector<std::size_t> cut;
      for (std::size_t i = 0; i < actions_.size(); ++i)
        if (pcf[i] >= 0 && before[pcf[i]] && zone[actions_[i].add]) {
          cut.push_back(i);
          m = std::min(m, cost[i]);
        }
      if (cut.empty() || m <= 0) return h;  // cannot happen with a positive h_max; stay sound
      h += m;
      for (std::size_t i : cut) cost[i] -= m;
    }
  }

 private:
  int Fact(int a, int l) const { return offset_[a] + l; }

  // The goal fact needs one of the goal's alternatives (a fact of its own), with `clauses` each of
  // its clauses too (one fact each: "every person rescued by some robot" is n clauses where its
  // alternatives number n^n, beyond the cap at which they read as true), and the locations the
  // episodes and temporal constraints need. Every plan meets all of them, so reading the goal
  // both ways is still a relaxation.
  void AddGoal(const StatePlan& sp, bool clauses) {
    Action goal{{}, goal_, 0};
    Atoms visits;
    for (const auto& e : sp.episodes) RequiredLocations(e.accepting.expr, visits);
    for (const auto& t : sp.temporals) {
      RequiredLocations(t.event1.expr, visits);
      RequiredLocations(t.event2.expr, visits);
    }
    for (auto [a, l] : visits) goal.pre.push_back(Fact(a, l));
    const int alternative = facts_++;
    goal.pre.push_back(alternative);
    for (const Atoms& alt : Alternatives(sp.goal.expr)) {
      Action act{{}, alternative, 0};
      for (auto [a, l] : alt) act.pre.push_back(Fact(a, l));
      actions_.push_back(std::move(act));
    }
    for (const Clause& c : clauses ? ToClauses(sp.goal.expr) : Clauses{}) {
      const int clause = facts_++;
      goal.pre.push_back(clause);
      for (auto [a, l] : c) actions_.push_back(Action{{Fact(a, l)}, clause, 0});
    }
    actions_.push_back(std::move(goal));
  }

  // h_max of every fact under the given action costs (a fixpoint; costs are non-negative).
  std::vector<long> HMax(const std::vector<long>& cost) {
    std::vector<long> h(facts_, kInf);
    for (int f : init_) h[f] = 0;
    for (bool changed = true; changed;) {
      changed = false;
      work_ += static_cast<long>(actions_.size());
      for (std::size_t i = 0; i < actions_.size(); ++i) {
        long pre = 0;
        for (int p : actions_[i].pre) pre = std::max(pre, h[p]);
        if (pre >= kInf) continue;
        if (pre + cost[i] < h[actions_[i].add]) {
          h[actions_[i].add] = pre + cost[i];
          changed = true;
        }
      }
    }
    return h;
  }

  // Each action's precondition of greatest h_max (-1 when unreachable); an action without
  // precondition hangs from the first initial fact.
  std::vector<int> Supporters(const std::vector<long>& hmax) {
    work_ += static_cast<long>(actions_.size());
    std::vector<int> pcf(actions_.size(), -1);
    for (std::size_t i = 0; i < actions_.size(); ++i) {
      int best = actions_[i].pre.empty() ? init_.front() : -1;
      for (int p : actions_[i].pre)
        if (best < 0 || hmax[p] > hmax[best]) best = p;
      if (best >= 0 && hmax[best] < kInf) pcf[i] = best;
    }
    return pcf;
  }

  // Facts from which the goal is reached over zero-cost edges of the justification graph.
  std::vector<char> GoalZone(const std::vector<int>& pcf, const std::vector<long>& cost) {
    std::vector<char> zone(facts_, 0);
    zone[goal_] = 1;
    for (bool changed = true; changed;) {
      changed = false;
      work_ += static_cast<long>(actions_.size());
      for (std::size_t i = 0; i < actions_.size(); ++i)
        if (pcf[i] >= 0 && cost[i] == 0 && zone[actions_[i].add] && !zone[pcf[i]])
          zone[pcf[i]] = changed = 1;
    }
    return zone;
  }

  // Facts reached from the initial facts without entering the goal zone.
  std::vector<char> BeforeZone(const std::vector<int>& pcf, const std::vector<char>& zone) {
    std::vector<char> seen(facts_, 0);
    for (int f : init_)
      if (!zone[f]) seen[f] = 1;
    for (bool changed = true; changed;) {
      changed = false;
      work_ += static_cast<long>(actions_.size());
      for (std::size_t i = 0; i < actions_.size(); ++i) {
        const int to = actions_[i].add;
        if (pcf[i] >= 0 && seen[pcf[i]] && !zone[to] && !seen[to]) seen[to] = changed = 1;
      }
    }
    return seen;
  }

  std::vector<int> offset_, init_;
  int facts_ = 0, goal_ = 0;
  std::vector<Action> actions_;
  long work_ = 0;  // action visits so far, all rounds (kMaxLmCutWork)
};

}  // namespace

std::optional<long> RelaxedCostBound(const Domain& d, const StatePlan& sp) {
  return RelaxedTask(d, sp).LmCut();
}

std::optional<long> RelaxedCostOfOthers(const Domain& d, const StatePlan& sp,
                                        const std::vector<char>& free_automata) {
  return RelaxedTask(d, sp, free_automata, {}, true).LmCut();
}

bool RelaxedReachableAvoiding(const Domain& d, const StatePlan& sp,
                              const std::vector<std::pair<int, int>>& facts) {
  return RelaxedTask(d, sp, {}, facts, true).Reachable();
}

}  // namespace ctb
