// Internal to planner/analyze: the over-approximation of the runs that the static checks and the
// time network reason on (analyze.h describes it; docs/explain.md gives the argument). Not a
// public header: the types change with the checks.
#pragma once

#include <algorithm>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "planner/model/domain.h"
#include "planner/model/state_plan.h"

namespace ctb::analysis {

inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr long kSearchBudget = 200000;  // nodes per satisfiability question; beyond: "maybe"

enum class Tv { kFalse, kTrue, kUnknown };

inline Tv Not(Tv a) { return a == Tv::kUnknown ? a : (a == Tv::kTrue ? Tv::kFalse : Tv::kTrue); }
inline Tv And(Tv a, Tv b) {
  if (a == Tv::kFalse || b == Tv::kFalse) return Tv::kFalse;
  if (a == Tv::kTrue && b == Tv::kTrue) return Tv::kTrue;
  return Tv::kUnknown;
}
inline Tv Or(Tv a, Tv b) { return Not(And(Not(a), Not(b))); }

// One automaton's situation at an event: the location on the stage before and after it.
struct Opt {
  int prev = 0, next = 0;
};

// One condition to satisfy at an event. `change`: [i] reads the stage before the event (an
// accepting condition that describes a change); otherwise every index reads the stage after it.
// `before`: every index reads the stage before the event (a guard, or a maintenance constraint
// on the stage that ends at the event).
struct Term {
  const Expr* e = nullptr;
  bool change = false;
  bool before = false;
};

inline Term AtEvent(const Condition& c) { return {&c.raw, c.raw_info.IsChange()}; }
inline Term OnStage(const Condition& c) { return {&c.raw, false}; }
inline Term OnStageBefore(const Condition& c) { return {&c.raw, false, true}; }

// Per automaton and option (the shape of an option list): the guard of the transition the option
// takes, or nullptr for a stay or an unguarded transition.
using OptGuards = std::vector<std::vector<const Expr*>>;

// Satisfiability of a conjunction of terms over per-automaton option lists, by depth-first
// search with three-valued evaluation. Atoms over commands, accepting automata and fixed stages
// other than 0 are unknown, so "unsatisfiable" is a proof and "satisfiable" may be a guess.
class SatSearch {
 public:
  // With `guards` (same shape as opts, not owned), an option that moves an automaton also needs
  // its transition's guard on the stage before the event, and the automata the guards read are
  // searched too.
  SatSearch(const std::vector<int>& init, const std::vector<std::vector<Opt>>& opts,
            const std::vector<Term>& terms, const OptGuards* guards = nullptr)
      : init_(init), opts_(opts), terms_(terms), guards_(guards), pick_(opts.size(), -1) {
    std::set<int> read;
    for (const auto& t : terms) Collect(*t.e, read);
    for (std::vector<int> todo(read.begin(), read.end()); guards_ && !todo.empty();) {
      const int a = todo.back();
      todo.pop_back();
      std::set<int> more;
      for (const Expr* g : (*guards_)[a])
        if (g) Collect(*g, more);
      for (int b : more)
        if (read.insert(b).second) todo.push_back(b);
    }
    order_.assign(read.begin(), read.end());
    std::stable_sort(order_.begin(), order_.end(),
                     [&](int a, int b) { return opts_[a].size() < opts_[b].size(); });
  }

  // True unless no assignment can satisfy every term. With fix_a >= 0, that automaton is pinned
  // to option fix_o.
  bool Run(int fix_a = -1, int fix_o = -1) {
    budget_ = kSearchBudget;
    std::fill(pick_.begin(), pick_.end(), -1);
    if (fix_a >= 0) pick_[fix_a] = fix_o;
    return Dfs(0);
  }

  const std::vector<int>& order() const { return order_; }

 private:
  static void Collect(const Expr& e, std::set<int>& out) {
    if (e.op == Expr::Op::kAtom) {
      if (e.var_kind == VarKind::kLocation) out.insert(e.target);
      return;
    }
    for (const auto& k : e.kids) Collect(k, out);
  }

  // `change`: [i] reads the stage before; `before`: every index does.
  Tv Eval(const Expr& e, bool change, bool before = false) const {
    switch (e.op) {
      case Expr::Op::kTrue: return Tv::kTrue;
      case Expr::Op::kFalse: return Tv::kFalse;
      case Expr::Op::kNot: return Not(Eval(e.kids[0], change, before));
      case Expr::Op::kAnd: {  // a false (true) side decides a conjunction (disjunction) alone
        const Tv a = Eval(e.kids[0], change, before);
        return a == Tv::kFalse ? a : And(a, Eval(e.kids[1], change, before));
      }
      case Expr::Op::kOr: {
        const Tv a = Eval(e.kids[0], change, before);
        return a == Tv::kTrue ? a : Or(a, Eval(e.kids[1], change, before));
      }
      case Expr::Op::kImplies:
        return Or(Not(Eval(e.kids[0], change, before)), Eval(e.kids[1], change, before));
      case Expr::Op::kIff: {
        Tv a = Eval(e.kids[0], change, before), b = Eval(e.kids[1], change, before);
        if (a == Tv::kUnknown || b == Tv::kUnknown) return Tv::kUnknown;
        return a == b ? Tv::kTrue : Tv::kFalse;
      }
      case Expr::Op::kAtom:
      case Expr::Op::kEvery:  // quantifiers are expanded at load: unknown if one were left
      case Expr::Op::kAny: break;
    }
    if (e.var_kind != VarKind::kLocation) return Tv::kUnknown;
    int value;
    if (e.index.kind == IndexKind::kFixed) {
      if (e.index.fixed != 0) return Tv::kUnknown;
      value = init_[e.target];
    } else {
      int p = pick_[e.target];
      if (p < 0) return Tv::kUnknown;
      const Opt& o = opts_[e.target][p];
      value = (before || (change && e.index.kind == IndexKind::kI)) ? o.prev : o.next;
    }
    return (value == e.value_code) != e.not_equal ? Tv::kTrue : Tv::kFalse;
  }

  Tv EvalAll() const {
    Tv r = Tv::kTrue;
    for (const auto& t : terms_) {
      r = And(r, Eval(*t.e, t.change, t.before));
      if (r == Tv::kFalse) return r;
    }
    if (!guards_) return r;
    for (std::size_t a = 0; a < pick_.size(); ++a) {
      if (pick_[a] < 0) continue;
      const Expr* g = (*guards_)[a][pick_[a]];
      if (g) r = And(r, Eval(*g, false, true));
      if (r == Tv::kFalse) return r;
    }
    return r;
  }

  bool Dfs(std::size_t k) {
    if (--budget_ < 0) return true;  // out of budget: cannot prove anything
    Tv now = EvalAll();
    if (now == Tv::kFalse) return false;
    if (now == Tv::kTrue) return true;
    while (k < order_.size() && pick_[order_[k]] >= 0) ++k;
    if (k == order_.size()) return true;  // unknown atoms only: may hold
    int a = order_[k];
    for (int o = 0; o < static_cast<int>(opts_[a].size()); ++o) {
      pick_[a] = o;
      if (Dfs(k + 1)) {
        pick_[a] = -1;
        return true;
      }
    }
    pick_[a] = -1;
    return false;
  }

  const std::vector<int>& init_;
  const std::vector<std::vector<Opt>>& opts_;
  const std::vector<Term>& terms_;
  const OptGuards* guards_;
  std::vector<int> pick_;
  std::vector<int> order_;
  long budget_ = 0;
};

// The over-approximation of the runs (see the header), optionally under a maintenance
// constraint that every stage before the goal event must satisfy.
struct Abstraction {
  const Domain* d = nullptr;
  std::vector<int> init;
  bool only_initial = false;                 // the maintenance constraint fails on stage 0
  std::vector<std::vector<char>> reach;      // [a][l]: on some stage up to the goal event
  std::vector<std::vector<char>> usable;     // [a][t]: can fire at some event up to the goal
  std::vector<std::vector<Opt>> event_opts;  // per automaton: stays and usable transitions
  OptGuards event_guards;                    // per event option: its transition's guard
  std::vector<std::vector<Opt>> stage_opts;  // per automaton: reachable locations
  std::vector<std::vector<double>> dist;     // [a][from * n + to]: least time between entries

  double Dist(int a, int from, int to) const {
    const int n = static_cast<int>(d->automata[a].locations.size());
    return dist[a][from * n + to];
  }
  // Least time from a stage in `from` (entered at that event when `entered`, else earlier) to
  // a later stage in `to`: when `from` was entered earlier, its first transition's lower
  // duration may have elapsed already.
  double Gap(int a, int from, bool entered, int to) const {
    if (from == to) return 0;
    if (entered) return Dist(a, from, to);
    double best = kInf;
    const Automaton& au = d->automata[a];
    for (std::size_t t = 0; t < au.transitions.size(); ++t)
      if (usable[a][t] && au.transitions[t].from == from)
        best = std::min(best, Dist(a, au.transitions[t].to, to));
    return best;
  }
};

std::vector<std::vector<Opt>> StageOpts(const std::vector<std::vector<char>>& reach);

// allowed[a][l]: the locations the maintenance constraint admits (all when null).
Abstraction Build(const Domain& d, const StatePlan& sp,
                  const std::vector<std::vector<char>>* allowed);

// Whether the terms can hold together at one event of the abstraction.
bool MayHold(const Abstraction& ab, const std::vector<Term>& terms);

// For each automaton, the options (at one event) compatible with the terms; automata the terms
// do not read keep every option. With `guards`, an option that moves an automaton needs its
// transition's guard on the stage before (Abstraction::event_guards), which ties automata
// together (a connection made only while the computer is off).
std::vector<std::vector<Opt>> Project(const Abstraction& ab, const std::vector<Term>& terms,
                                      bool guards = false);

// Least time from an event at which `from` holds to a later (or the same) event at which `to`
// holds.
double LeastGap(const Abstraction& ab, const std::vector<std::vector<Opt>>& from,
                const std::vector<std::vector<Opt>>& to);

}  // namespace ctb::analysis
