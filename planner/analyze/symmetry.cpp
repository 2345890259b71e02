#include "planner/analyze/symmetry.h"

#include <algorithm>
#include <deque>
#include <optional>
#include <set>
#include <string>

#include "planner/expr/normalize.h"

namespace ctb {

namespace {

// How a tree is renamed before it is printed canonically. Null maps are the identity.
struct Renaming {
  const std::vector<int>* automata = nullptr;
  const std::vector<int>* episodes = nullptr;
  const std::vector<int>* temporals = nullptr;
  int self = -1;                  // >= 0: automaton `self` prints as "s", every other one as "*"
  bool any_state_target = false;  // episode and temporal states print their target as "*"
};

int Mapped(const std::vector<int>* m, int x) { return m ? (*m)[x] : x; }

std::string Target(const Expr& atom, const Renaming& r) {
  switch (atom.var_kind) {
    case VarKind::kLocation:
    case VarKind::kCommand:
      if (r.self >= 0) return atom.target == r.self ? "s" : "*";
      return std::to_string(Mapped(r.automata, atom.target));
    case VarKind::kEpisodeState:
      return r.any_state_target ? "*" : std::to_string(Mapped(r.episodes, atom.target));
    case VarKind::kTemporalState:
      return r.any_state_target ? "*" : std::to_string(Mapped(r.temporals, atom.target));
    case VarKind::kUnresolved: break;
  }
  return "?";
}

// The atom without its target: kind, stage index, (in)equality and value code.
std::string AtomShape(const Expr& atom) {
  static const char* kKinds = "?LUEC";
  std::string s(1, kKinds[static_cast<int>(atom.var_kind)]);
  switch (atom.index.kind) {
    case IndexKind::kI: s += "@i"; break;
    case IndexKind::kIPlus1: s += "@j"; break;
    case IndexKind::kFixed: s += "@#" + std::to_string(atom.index.fixed); break;
  }
  return s + (atom.not_equal ? "!" : "=") + std::to_string(atom.value_code);
}

// A string equal for two trees when they are equal up to the order of the operands of /\, \/
// (flattened) and <->, after renaming. `ok` turns false on an unresolved atom (never equal).
std::string Canon(const Expr& e, const Renaming& r, bool& ok) {
  using Op = Expr::Op;
  switch (e.op) {
    case Op::kTrue: return "T";
    case Op::kFalse: return "F";
    case Op::kAtom:
      if (e.var_kind == VarKind::kUnresolved) ok = false;
      return AtomShape(e) + "/" + Target(e, r);
    case Op::kNot: return "!(" + Canon(e.kids.at(0), r, ok) + ")";
    case Op::kAnd:
    case Op::kOr: {
      std::vector<const Expr*> operands;
      Flatten(e, e.op, operands);
      std::vector<std::string> parts;
      for (const Expr* x : operands) parts.push_back(Canon(*x, r, ok));
      std::sort(parts.begin(), parts.end());
      std::string s = e.op == Op::kAnd ? "&(" : "|(";
      for (std::size_t i = 0; i < parts.size(); ++i) s += (i ? "," : "") + parts[i];
      return s + ")";
    }
    case Op::kIff: {
      std::string a = Canon(e.kids.at(0), r, ok), b = Canon(e.kids.at(1), r, ok);
      if (b < a) std::swap(a, b);
      return "=(" + a + "," + b + ")";
    }
    case Op::kImplies:
      return ">(" + Canon(e.kids.at(0), r, ok) + "," + Canon(e.kids.at(1), r, ok) + ")";
    case Op::kEvery:  // expanded at load (quantify.h); never equal if one were left
    case Op::kAny: break;
  }
  ok = false;
  return "?";
}

// Canon of a condition, with its classification (change or state) and ok folded in: two
// conditions are interchangeable exactly when their strings are equal and not empty.
std::string CondCanon(const Condition& c, const Renaming& r) {
  bool ok = true;
  std::string s = Canon(c.expr, r, ok);
  if (!ok) return "";
  return (c.info.IsChange() ? "c:" : "s:") + s;
}

// Everything about an automaton but its name and guards.
std::string ShapeOf(const Automaton& a, int initial) {
  std::string s = std::to_string(initial) + "|";
  for (const auto& l : a.locations) s += l + ",";
  s += "|";
  for (const auto& c : a.commands) s += c + ",";
  for (const auto& t : a.transitions)
    s += "|" + std::to_string(t.from) + ">" + std::to_string(t.to) + ":" +
         std::to_string(t.duration.lo) + "-" +
         (t.duration.hi ? std::to_string(*t.duration.hi) : std::string("inf")) + "$" +
         std::to_string(t.cost) + (t.controllable ? "C" : "") + (t.commanded ? "M" : "") +
         std::to_string(t.command);
  return s;
}

// The shapes of the atoms on automaton a in e, sorted (a multiset every symmetry preserves).
std::string AtomsOn(const Expr& e, int a) {
  std::vector<std::string> shapes;
  std::vector<const Expr*> stack{&e};
  while (!stack.empty()) {
    const Expr* x = stack.back();
    stack.pop_back();
    if (x->op == Expr::Op::kAtom &&
        (x->var_kind == VarKind::kLocation || x->var_kind == VarKind::kCommand) && x->target == a)
      shapes.push_back(AtomShape(*x));
    for (const auto& k : x->kids) stack.push_back(&k);
  }
  std::sort(shapes.begin(), shapes.end());
  std::string s;
  for (const auto& x : shapes) s += x + ",";
  return s;
}

std::string Sorted(std::vector<std::string> v) {
  std::sort(v.begin(), v.end());
  std::string s;
  for (const auto& x : v) s += x + ";";
  return s;
}

std::string Bounds(double lo, double hi) { return std::to_string(lo) + "," + std::to_string(hi); }

// The checks, with what does not depend on the exchange computed once.
class Checker {
 public:
  Checker(const Domain& d, const StatePlan& sp) : d_(d), sp_(sp) {
    const std::size_t na = d.automata.size();
    guards_.resize(na);
    reads_.resize(na);
    for (std::size_t a = 0; a < na; ++a) {
      shapes_.push_back(ShapeOf(d.automata[a], a < sp.initial.size() ? sp.initial[a] : -1));
      for (const auto& t : d.automata[a].transitions) {
        bool ok = true;
        guards_[a].push_back(Canon(t.guard, Renaming{}, ok));
        if (!ok) guards_[a].back().clear();  // an empty string never equals a canon
        for (int x : t.guard_info.locations_read) reads_[a].insert(x);
        for (int x : t.guard_info.commands_read) reads_[a].insert(x);
      }
    }
    Renaming any;
    any.any_state_target = true;
    for (const auto& ep : sp.episodes) {
      episodes_.push_back(EpisodeCanon(ep, Renaming{}));
      episodes_any_.push_back(EpisodeCanon(ep, any));
    }
    for (const auto& tc : sp.temporals) {
      temporals_.push_back(TemporalCanon(tc, Renaming{}));
      temporals_any_.push_back(TemporalCanon(tc, any));
    }
    goal_ = CondCanon(sp.goal, Renaming{});
    maintenance_ = CondCanon(sp.maintenance, Renaming{});
    for (const auto& ev : sp.events) events_.push_back(EventCanon(ev, nullptr, nullptr));
    std::sort(events_.begin(), events_.end());
  }

  // What every symmetry preserves about automaton a: a necessary condition for exchanging two.
  std::string Signature(int a) const {
    Renaming self;
    self.self = a;
    std::string s = shapes_[a] + "#";
    for (const auto& t : d_.automata[a].transitions) {
      bool ok = true;
      s += Canon(t.guard, self, ok) + (ok ? ";" : "?;");
    }
    s += "#" + AtomsOn(sp_.goal.expr, a) + "#" + AtomsOn(sp_.maintenance.expr, a) + "#";
    std::vector<std::string> eps, tcs;
    for (const auto& ep : sp_.episodes)
      eps.push_back(AtomsOn(ep.accepting.expr, a) + "/" + AtomsOn(ep.state.expr, a));
    for (const auto& tc : sp_.temporals)
      tcs.push_back(AtomsOn(tc.event1.expr, a) + "/" + AtomsOn(tc.event2.expr, a));
    return s + Sorted(eps) + "#" + Sorted(tcs);
  }

  bool IsSymmetry(const std::vector<int>& perm) const {
    const std::size_t na = d_.automata.size();
    if (perm.size() != na || sp_.initial.size() != na) return false;
    std::vector<bool> moved(na, false);
    for (std::size_t a = 0; a < na; ++a) {
      const int b = perm[a];
      if (b < 0 || b >= static_cast<int>(na) || perm[b] != static_cast<int>(a)) return false;
      moved[a] = b != static_cast<int>(a);
    }
    return DomainMaps(perm, moved) && StatePlanMaps(perm);
  }

 private:
  // Every automaton that moves or reads one that moves: its guards, renamed, are its image's.
  bool DomainMaps(const std::vector<int>& perm, const std::vector<bool>& moved) const {
    Renaming r;
    r.automata = &perm;
    for (std::size_t a = 0; a < d_.automata.size(); ++a) {
      const bool reads_moved =
          std::any_of(reads_[a].begin(), reads_[a].end(), [&](int x) { return moved[x]; });
      if (!moved[a] && !reads_moved) continue;
      const int b = perm[a];
      if (shapes_[a] != shapes_[b]) return false;
      const auto& ts = d_.automata[a].transitions;
      for (std::size_t k = 0; k < ts.size(); ++k) {
        bool ok = true;
        std::string mine = Canon(ts[k].guard, r, ok);
        if (!ok || guards_[b][k].empty() || mine != guards_[b][k]) return false;
      }
    }
    return true;
  }

  bool StatePlanMaps(const std::vector<int>& perm) const {
    Renaming any;
    any.automata = &perm;
    any.any_state_target = true;
    // The bijections on episodes and temporal constraints: matched first with their states'
    // targets ignored (the identity preferred), then checked exactly.
    std::vector<int> pi, rho;
    if (!Match(sp_.episodes, episodes_any_, any, pi) ||
        !Match(sp_.temporals, temporals_any_, any, rho))
      return false;
    Renaming r;
    r.automata = &perm;
    r.episodes = &pi;
    r.temporals = &rho;
    for (std::size_t p = 0; p < sp_.episodes.size(); ++p)
      if (EpisodeCanon(sp_.episodes[p], r) != episodes_[pi[p]]) return false;
    for (std::size_t q = 0; q < sp_.temporals.size(); ++q)
      if (TemporalCanon(sp_.temporals[q], r) != temporals_[rho[q]]) return false;
    if (goal_.empty() || CondCanon(sp_.goal, r) != goal_) return false;
    if (maintenance_.empty() || CondCanon(sp_.maintenance, r) != maintenance_) return false;
    std::vector<std::string> events;
    for (const auto& ev : sp_.events) events.push_back(EventCanon(ev, &pi, &rho));
    std::sort(events.begin(), events.end());
    return events == events_;
  }

  // out[p] = q: the image of item p is item q, the first unused q (p itself first) whose canon
  // with states' targets ignored equals p's renamed one. False when some p has none.
  template <typename Item>
  bool Match(const std::vector<Item>& items, const std::vector<std::string>& targets,
             const Renaming& r, std::vector<int>& out) const {
    const std::size_t n = items.size();
    out.assign(n, -1);
    std::vector<bool> used(n, false);
    for (std::size_t p = 0; p < n; ++p) {
      const std::string mine = ItemCanon(items[p], r);
      if (mine.empty()) return false;
      int pick = !used[p] && targets[p] == mine ? static_cast<int>(p) : -1;
      for (std::size_t q = 0; q < n && pick < 0; ++q)
        if (!used[q] && targets[q] == mine) pick = static_cast<int>(q);
      if (pick < 0) return false;
      used[pick] = true;
      out[p] = pick;
    }
    return true;
  }
  static std::string ItemCanon(const Episode& ep, const Renaming& r) { return EpisodeCanon(ep, r); }
  static std::string ItemCanon(const Temporal& tc, const Renaming& r) {
    return TemporalCanon(tc, r);
  }

  static std::string EpisodeCanon(const Episode& ep, const Renaming& r) {
    std::string a = CondCanon(ep.accepting, r), s = CondCanon(ep.state, r);
    if (a.empty() || s.empty()) return "";
    return a + "|" + s + "|" + Bounds(ep.lower, ep.upper);
  }
  static std::string TemporalCanon(const Temporal& tc, const Renaming& r) {
    std::string a = CondCanon(tc.event1, r), b = CondCanon(tc.event2, r);
    if (a.empty() || b.empty()) return "";
    return a + "|" + b + "|" + Bounds(tc.lower, tc.upper);
  }
  static std::string EventCanon(const SharedEvent& ev, const std::vector<int>* pi,
                                const std::vector<int>* rho) {
    std::vector<std::string> ends;
    for (const auto& p : ev.endpoints) {
      const bool episode =
          p.kind == EndpointKind::kEpisodeStart || p.kind == EndpointKind::kEpisodeEnd;
      ends.push_back(std::to_string(static_cast<int>(p.kind)) + ":" +
                     std::to_string(Mapped(episode ? pi : rho, p.index)));
    }
    return Sorted(ends);
  }

  const Domain& d_;
  const StatePlan& sp_;
  std::vector<std::string> shapes_;               // ShapeOf per automaton
  std::vector<std::vector<std::string>> guards_;  // canon per automaton and transition
  std::vector<std::set<int>> reads_;              // automata an automaton's guards read
  std::vector<std::string> episodes_, episodes_any_, temporals_, temporals_any_, events_;
  std::string goal_, maintenance_;
};

// The exchange forced by exchanging a and b: walking a's guards beside b's (same shape, operands
// in place), an automaton read at one place must map to the one read at the same place in the
// other. Fills perm (an involution, identity where nothing forced a move) and side (the moved
// automata on a's side, a first, in the order they were forced). False on a contradiction.
class Closure {
 public:
  Closure(const Domain& d, const std::vector<std::string>& signatures) : d_(d), sig_(signatures) {}

  bool Run(int a, int b, std::vector<int>& perm, std::vector<int>& side) {
    perm_.assign(d_.automata.size(), -1);
    side_.clear();
    queue_.clear();
    if (!Pair(a, b)) return false;
    while (!queue_.empty()) {
      const int x = queue_.front(), y = perm_[x];
      queue_.pop_front();
      if (sig_[x] != sig_[y]) return false;
      const auto& tx = d_.automata[x].transitions;
      const auto& ty = d_.automata[y].transitions;
      if (tx.size() != ty.size()) return false;
      for (std::size_t k = 0; k < tx.size(); ++k)
        if (!Walk(tx[k].guard, ty[k].guard)) return false;
    }
    for (std::size_t c = 0; c < perm_.size(); ++c)
      if (perm_[c] < 0) perm_[c] = static_cast<int>(c);
    perm = perm_;
    side = side_;
    return true;
  }

 private:
  bool Pair(int x, int y) {
    if (x == y || perm_[x] >= 0 || perm_[y] >= 0) return false;
    perm_[x] = y;
    perm_[y] = x;
    side_.push_back(x);
    queue_.push_back(x);
    return true;
  }

  bool Walk(const Expr& x, const Expr& y) {
    if (x.op != y.op || x.kids.size() != y.kids.size()) return false;
    for (std::size_t k = 0; k < x.kids.size(); ++k)
      if (!Walk(x.kids[k], y.kids[k])) return false;
    if (x.op != Expr::Op::kAtom) return true;
    if (x.var_kind != y.var_kind) return false;
    if (x.var_kind != VarKind::kLocation && x.var_kind != VarKind::kCommand) return true;
    const int c = x.target, c2 = y.target;
    if (perm_[c] >= 0) return perm_[c] == c2;
    if (perm_[c2] >= 0) return false;
    if (c == c2) {
      perm_[c] = c;
      return true;
    }
    return Pair(c, c2);
  }

  const Domain& d_;
  const std::vector<std::string>& sig_;
  std::vector<int> perm_;
  std::vector<int> side_;
  std::deque<int> queue_;
};

bool Disjoint(const std::vector<int>& xs, const std::vector<bool>& taken) {
  return std::none_of(xs.begin(), xs.end(), [&](int x) { return taken[x]; });
}

}  // namespace

bool IsSymmetry(const Domain& d, const StatePlan& sp, const std::vector<int>& perm) {
  // Actions name automata outside the conditions the checker compares: only the identity.
  if (sp.HasActionRules() || !sp.actions.empty()) {
    for (std::size_t a = 0; a < perm.size(); ++a)
      if (perm[a] != static_cast<int>(a)) return false;
    return perm.size() == d.automata.size();
  }
  return Checker(d, sp).IsSymmetry(perm);
}

std::vector<SymmetryOrbit> FindSymmetries(const Domain& d, const StatePlan& sp) {
  const int na = static_cast<int>(d.automata.size());
  std::vector<SymmetryOrbit> out;
  if (na < 2 || static_cast<int>(sp.initial.size()) != na) return out;
  if (sp.HasActionRules() || !sp.actions.empty()) return out;  // as IsSymmetry
  Checker check(d, sp);
  std::vector<std::string> sig;
  for (int a = 0; a < na; ++a) sig.push_back(check.Signature(a));
  Closure closure(d, sig);
  std::vector<bool> used(na, false);  // in an orbit already
  for (int a = 0; a < na; ++a) {
    if (used[a]) continue;
    std::vector<bool> taken = used;  // used, or in this orbit's units
    std::vector<int> unit0;
    std::vector<std::vector<int>> units;
    for (int b = a + 1; b < na; ++b) {
      if (taken[b] || sig[b] != sig[a]) continue;
      std::vector<int> perm, side;
      if (!closure.Run(a, b, perm, side)) continue;
      std::vector<int> image;
      for (int x : side) image.push_back(perm[x]);
      if (!Disjoint(image, taken)) continue;
      if (unit0.empty() ? !Disjoint(side, taken)
                        : std::set<int>(side.begin(), side.end()) !=
                              std::set<int>(unit0.begin(), unit0.end()))
        continue;
      if (!check.IsSymmetry(perm)) continue;
      if (unit0.empty()) {
        unit0 = side;
        for (int x : unit0) taken[x] = true;
      }
      std::vector<int> unit;
      for (int x : unit0) unit.push_back(perm[x]);
      for (int x : unit) taken[x] = true;
      units.push_back(unit);
    }
    if (units.empty()) continue;
    SymmetryOrbit orbit;
    orbit.units.push_back(unit0);
    for (auto& u : units) orbit.units.push_back(std::move(u));
    for (const auto& u : orbit.units)
      for (int x : u) used[x] = true;
    out.push_back(std::move(orbit));
  }
  return out;
}

}  // namespace ctb
