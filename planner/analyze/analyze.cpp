#include "planner/analyze/analyze.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "planner/model/error.h"

namespace ctb {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr long kSearchBudget = 200000;  // nodes per satisfiability question; beyond: "maybe"

enum class Tv { kFalse, kTrue, kUnknown };

Tv Not(Tv a) { return a == Tv::kUnknown ? a : (a == Tv::kTrue ? Tv::kFalse : Tv::kTrue); }
Tv And(Tv a, Tv b) {
  if (a == Tv::kFalse || b == Tv::kFalse) return Tv::kFalse;
  if (a == Tv::kTrue && b == Tv::kTrue) return Tv::kTrue;
  return Tv::kUnknown;
}
Tv Or(Tv a, Tv b) { return Not(And(Not(a), Not(b))); }

// One automaton's situation at an event: the location on the stage before and after it.
struct Opt {
  int prev = 0, next = 0;
};

// One condition to satisfy at an event. `change`: [i] reads the stage before the event (an
// accepting condition that describes a change); otherwise every index reads the stage after it.
struct Term {
  const Expr* e = nullptr;
  bool change = false;
};

Term AtEvent(const Condition& c) { return {&c.raw, c.raw_info.IsChange()}; }
Term OnStage(const Condition& c) { return {&c.raw, false}; }

// Satisfiability of a conjunction of terms over per-automaton option lists, by depth-first
// search with three-valued evaluation. Atoms over commands, accepting automata and fixed stages
// other than 0 are unknown, so "unsatisfiable" is a proof and "satisfiable" may be a guess.
class SatSearch {
 public:
  SatSearch(const std::vector<int>& init, const std::vector<std::vector<Opt>>& opts,
            const std::vector<Term>& terms)
      : init_(init), opts_(opts), terms_(terms), pick_(opts.size(), -1) {
    std::set<int> read;
    for (const auto& t : terms) Collect(*t.e, read);
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

  Tv Eval(const Expr& e, bool change) const {
    switch (e.op) {
      case Expr::Op::kTrue: return Tv::kTrue;
      case Expr::Op::kFalse: return Tv::kFalse;
      case Expr::Op::kNot: return Not(Eval(e.kids[0], change));
      case Expr::Op::kAnd: return And(Eval(e.kids[0], change), Eval(e.kids[1], change));
      case Expr::Op::kOr: return Or(Eval(e.kids[0], change), Eval(e.kids[1], change));
      case Expr::Op::kImplies: return Or(Not(Eval(e.kids[0], change)), Eval(e.kids[1], change));
      case Expr::Op::kIff: {
        Tv a = Eval(e.kids[0], change), b = Eval(e.kids[1], change);
        if (a == Tv::kUnknown || b == Tv::kUnknown) return Tv::kUnknown;
        return a == b ? Tv::kTrue : Tv::kFalse;
      }
      case Expr::Op::kAtom: break;
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
      value = (change && e.index.kind == IndexKind::kI) ? o.prev : o.next;
    }
    return (value == e.value_code) != e.not_equal ? Tv::kTrue : Tv::kFalse;
  }

  Tv EvalAll() const {
    Tv r = Tv::kTrue;
    for (const auto& t : terms_) {
      r = And(r, Eval(*t.e, t.change));
      if (r == Tv::kFalse) break;
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

bool GuardMayHold(const Transition& tr, int self, const std::vector<int>& init,
                  const std::vector<std::vector<Opt>>& stage_opts) {
  // The own automaton is in `from`: pin it by giving it that single option.
  std::vector<std::vector<Opt>> opts = stage_opts;
  opts[self] = {Opt{tr.from, tr.from}};
  std::vector<Term> terms{{&tr.guard, false}};
  SatSearch s(init, opts, terms);
  return s.Run();
}

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
    for (int l = 0; l < n; ++l)
      if (ab.reach[a][l] && !(ab.only_initial && l != sp.initial[a])) ab.event_opts[a].push_back({l, l});
    auto& dist = ab.dist[a];
    dist.assign(n * n, kInf);
    for (int l = 0; l < n; ++l) dist[l * n + l] = 0;
    for (std::size_t t = 0; t < au.transitions.size(); ++t) {
      if (!ab.usable[a][t]) continue;
      const Transition& tr = au.transitions[t];
      ab.event_opts[a].push_back({tr.from, tr.to});
      dist[tr.from * n + tr.to] = std::min(dist[tr.from * n + tr.to], tr.duration.lo);
    }
    for (int k = 0; k < n; ++k)
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
          dist[i * n + j] = std::min(dist[i * n + j], dist[i * n + k] + dist[k * n + j]);
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
std::vector<std::vector<Opt>> Project(const Abstraction& ab, const std::vector<Term>& terms) {
  std::vector<std::vector<Opt>> out = ab.event_opts;
  SatSearch s(ab.init, ab.event_opts, terms);
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

std::string Num(double v) {
  if (std::fabs(v - std::round(v)) < 1e-9) return std::to_string(std::llround(v));
  Json j(v);
  return j.dump();
}

std::string EpisodePointer(const Episode& e) { return "/constraints/episodes/" + PointerToken(e.name); }
std::string TemporalPointer(const Temporal& t) { return "/constraints/temporal/" + PointerToken(t.name); }
std::string EventPointer(const SharedEvent& e) { return "/constraints/event/" + PointerToken(e.name); }

// A reason in words why a condition cannot hold, from its top-level conjunction: a change no
// transition allows, or a location out of reach. Empty when no single atom pair explains it.
std::string WhyNever(const Domain& d, const Abstraction& ab, const Condition& c,
                     const std::vector<std::vector<char>>* allowed) {
  std::vector<const Expr*> atoms;
  std::vector<const Expr*> stack{&c.raw};
  while (!stack.empty()) {
    const Expr* e = stack.back();
    stack.pop_back();
    if (e->op == Expr::Op::kAnd) {
      stack.push_back(&e->kids[1]);
      stack.push_back(&e->kids[0]);
    } else if (e->op == Expr::Op::kAtom && e->var_kind == VarKind::kLocation && !e->not_equal &&
               e->index.kind != IndexKind::kFixed) {
      atoms.push_back(e);
    }
  }
  const bool change = c.raw_info.IsChange();
  for (const Expr* x : atoms) {
    const Automaton& au = d.automata[x->target];
    if (change && x->index.kind == IndexKind::kI) {
      for (const Expr* y : atoms) {
        if (y->target != x->target || y->index.kind != IndexKind::kIPlus1) continue;
        if (x->value_code == y->value_code) continue;
        bool exists = false;
        for (const auto& tr : au.transitions)
          exists = exists || (tr.from == x->value_code && tr.to == y->value_code);
        if (!exists)
          return "no transition takes " + au.name + " from " + au.locations[x->value_code] +
                 " to " + au.locations[y->value_code];
      }
    }
    if (!ab.reach[x->target][x->value_code]) {
      std::string why = au.name + " cannot reach " + au.locations[x->value_code] + " from " +
                        au.locations[ab.init[x->target]];
      return allowed ? why + " while the maintenance constraint holds" : why;
    }
  }
  return "";
}

class Checker {
 public:
  Checker(const Domain& d, const StatePlan& sp) : d_(d), sp_(sp) {}

  std::vector<StaticConflict> Run() {
    Abstraction plain = Build(d_, sp_, nullptr);
    Singles(plain, nullptr, {});
    SharedEvents(plain);
    if (sp_.maintenance.expr.op != Expr::Op::kTrue) {
      auto allowed = Allowed();
      Abstraction m = Build(d_, sp_, &allowed);
      if (m.only_initial) {
        Add({"never_holds", {sp_.goal.pointer, sp_.maintenance.pointer},
             "The maintenance constraint fails in the initial state, so the goal would have to "
             "hold at once, and it does not.",
             std::nullopt},
            !MayHold(m, {AtEvent(sp_.goal)}));
      }
      Singles(m, &allowed, sp_.maintenance.pointer);
    }
    return std::move(out_);
  }

 private:
  // The locations each automaton may occupy on a stage where the maintenance constraint holds.
  std::vector<std::vector<char>> Allowed() const {
    std::vector<std::vector<Opt>> all(d_.automata.size());
    for (std::size_t a = 0; a < d_.automata.size(); ++a)
      for (int l = 0; l < static_cast<int>(d_.automata[a].locations.size()); ++l)
        all[a].push_back({l, l});
    std::vector<Term> terms{OnStage(sp_.maintenance)};
    SatSearch s(sp_.initial, all, terms);
    std::vector<std::vector<char>> allowed(d_.automata.size());
    for (std::size_t a = 0; a < d_.automata.size(); ++a)
      allowed[a].assign(d_.automata[a].locations.size(), 1);
    for (int a : s.order())
      for (int l = 0; l < static_cast<int>(all[a].size()); ++l) allowed[a][l] = s.Run(a, l);
    return allowed;
  }

  // Adds c when `found`, unless a conflict already found uses a subset of its parts.
  void Add(StaticConflict c, bool found) {
    if (!found) return;
    std::set<std::string> mine(c.parts.begin(), c.parts.end());
    for (const auto& o : out_) {
      bool subset = true;
      for (const auto& p : o.parts) subset = subset && mine.count(p);
      if (subset) return;
    }
    out_.push_back(std::move(c));
  }

  // Checks of one part each (with the maintenance constraint as a second part when given).
  void Singles(const Abstraction& ab, const std::vector<std::vector<char>>* allowed,
               const std::string& maint) {
    auto parts = [&](const std::string& p) {
      std::vector<std::string> v{p};
      if (!maint.empty()) v.push_back(maint);
      return v;
    };
    const std::string under = maint.empty() ? "" : " while the maintenance constraint holds";
    auto reason = [&](const Condition& c) {
      std::string why = WhyNever(d_, ab, c, allowed);
      return why.empty() ? "" : ": " + why;
    };
    if (sp_.goal.expr.op != Expr::Op::kTrue)
      Add({"never_holds", parts(sp_.goal.pointer),
           "The goal can never be reached" + under + reason(sp_.goal) + ".", std::nullopt},
          !MayHold(ab, {AtEvent(sp_.goal)}));
    for (const auto& ep : sp_.episodes) {
      const std::string p = EpisodePointer(ep);
      if (!MayHold(ab, {AtEvent(ep.accepting)})) {
        Add({"never_holds", parts(p),
             "Episode " + ep.name + " can never start" + under + reason(ep.accepting) + ".",
             std::nullopt}, true);
      } else if (!MayHold(ab, {AtEvent(ep.accepting), OnStage(ep.state)})) {
        Add({"never_holds", parts(p),
             "Episode " + ep.name + " can never start: its state constraint cannot hold when its "
             "accepting constraint does" + under + ".", std::nullopt}, true);
      } else if (ab.only_initial) {
        Add({"never_holds", parts(p),
             "Episode " + ep.name + " needs an event after the start, but the maintenance "
             "constraint fails in the initial state.", std::nullopt}, true);
      }
    }
    for (const auto& tc : sp_.temporals) {
      const std::string p = TemporalPointer(tc);
      bool e1 = MayHold(ab, {AtEvent(tc.event1)}), e2 = MayHold(ab, {AtEvent(tc.event2)});
      if (!e1 || !e2) {
        const Condition& c = e1 ? tc.event2 : tc.event1;
        Add({"never_holds", parts(p),
             "Temporal constraint " + tc.name + " can never be met: its " +
                 (e1 ? "second" : "first") + " event can never happen" + under + reason(c) + ".",
             std::nullopt}, true);
        continue;
      }
      // Deadline: the least time between an event of one condition and a later one of the other.
      auto p1 = Project(ab, {AtEvent(tc.event1)}), p2 = Project(ab, {AtEvent(tc.event2)});
      double gap = std::min(LeastGap(ab, p1, p2), LeastGap(ab, p2, p1));
      if (MayHold(ab, {AtEvent(tc.event1), AtEvent(tc.event2)})) gap = 0;
      if (gap > tc.upper + 1e-9) {
        Add({"deadline", parts(p),
             "Temporal constraint " + tc.name + " allows at most " + Num(tc.upper) +
                 " s between its two events, but the automata need at least " + Num(gap) +
                 " s to get from one to the other" + under + ".",
             BoundHint{p + "/upper_bound", gap}}, true);
      }
    }
  }

  // Endpoints that must share one event but whose conditions cannot hold together.
  void SharedEvents(const Abstraction& ab) {
    for (const auto& ev : sp_.events) {
      // Per endpoint: the terms that hold at its event, and the part that owns it.
      struct End {
        std::vector<Term> terms;
        std::string part;
        std::string text;
      };
      std::vector<End> ends;
      std::map<std::string, std::set<EndpointKind>> kinds;
      for (const auto& e : ev.endpoints) {
        End x;
        x.text = e.text;
        switch (e.kind) {
          case EndpointKind::kEpisodeStart: {
            const Episode& ep = sp_.episodes[e.index];
            x.terms = {AtEvent(ep.accepting), OnStage(ep.state)};
            x.part = EpisodePointer(ep);
            break;
          }
          case EndpointKind::kEpisodeEnd:
            x.part = EpisodePointer(sp_.episodes[e.index]);
            break;
          case EndpointKind::kEvent1:
            x.terms = {AtEvent(sp_.temporals[e.index].event1)};
            x.part = TemporalPointer(sp_.temporals[e.index]);
            break;
          case EndpointKind::kEvent2:
            x.terms = {AtEvent(sp_.temporals[e.index].event2)};
            x.part = TemporalPointer(sp_.temporals[e.index]);
            break;
        }
        kinds[x.part].insert(e.kind);
        ends.push_back(std::move(x));
      }
      const std::string evp = EventPointer(ev);
      // An episode cannot start and end at one event.
      bool done = false;
      for (const auto& ep : sp_.episodes) {
        auto it = kinds.find(EpisodePointer(ep));
        if (it != kinds.end() && it->second.count(EndpointKind::kEpisodeStart) &&
            it->second.count(EndpointKind::kEpisodeEnd)) {
          Add({"shared_event", {evp, it->first},
               "Shared event " + ev.name + " puts the start and the end of episode " + ep.name +
                   " on one event, but an episode ends at a later event than it starts.",
               std::nullopt}, true);
          done = true;
        }
      }
      if (done) continue;
      auto holds = [&](const std::vector<int>& keep) {
        std::vector<Term> terms;
        for (int k : keep) terms.insert(terms.end(), ends[k].terms.begin(), ends[k].terms.end());
        return MayHold(ab, terms);
      };
      std::vector<int> keep;
      for (int k = 0; k < static_cast<int>(ends.size()); ++k) keep.push_back(k);
      if (holds(keep)) continue;
      // Deletion filter over the endpoints: a smallest set that still cannot hold together.
      for (int k = static_cast<int>(ends.size()) - 1; k >= 0; --k) {
        std::vector<int> rest;
        for (int x : keep)
          if (x != k) rest.push_back(x);
        if (!holds(rest)) keep = rest;
      }
      std::vector<std::string> parts{evp};
      std::string names;
      for (int k : keep) {
        if (std::find(parts.begin(), parts.end(), ends[k].part) == parts.end())
          parts.push_back(ends[k].part);
        names += (names.empty() ? "" : " and ") + ends[k].text;
      }
      Add({"shared_event", parts,
           "Shared event " + ev.name + " puts " + names +
               " on one event, but their conditions cannot hold at the same time.",
           std::nullopt}, true);
    }
  }

  const Domain& d_;
  const StatePlan& sp_;
  std::vector<StaticConflict> out_;
};

}  // namespace

std::vector<StaticConflict> FindStaticConflicts(const Domain& d, const StatePlan& sp) {
  auto out = Checker(d, sp).Run();
  std::stable_sort(out.begin(), out.end(), [](const StaticConflict& a, const StaticConflict& b) {
    return a.parts.size() < b.parts.size();
  });
  return out;
}

std::optional<StaticConflict> FindStaticConflict(const Domain& d, const StatePlan& sp) {
  auto all = FindStaticConflicts(d, sp);
  if (all.empty()) return std::nullopt;
  return all.front();
}

std::optional<double> ShortestTime(const Domain& d, const StatePlan& sp, int a, int from, int to) {
  Abstraction ab = Build(d, sp, nullptr);
  double v = ab.Dist(a, from, to);
  if (std::isinf(v)) return std::nullopt;
  return v;
}

}  // namespace ctb
