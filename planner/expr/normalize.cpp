#include "planner/expr/normalize.h"

#include <functional>
#include <map>
#include <set>
#include <tuple>
#include <utility>

namespace ctb {

namespace {

using Op = Expr::Op;

Expr Const(bool v) {
  Expr e;
  e.op = v ? Op::kTrue : Op::kFalse;
  return e;
}

Expr Unary(Op op, Expr kid) {
  Expr e;
  e.op = op;
  e.offset = kid.offset;
  e.kids.push_back(std::move(kid));
  return e;
}

Expr Binary(Op op, Expr a, Expr b) {
  Expr e;
  e.op = op;
  e.offset = a.offset;
  e.kids.push_back(std::move(a));
  e.kids.push_back(std::move(b));
  return e;
}

bool Resolved(const Expr& a) { return a.op == Op::kAtom && a.var_kind != VarKind::kUnresolved; }

// The variable an atom reads: kind, target and stage index.
using VarKey = std::tuple<int, int, int, int>;
VarKey KeyOf(const Expr& a) {
  return {static_cast<int>(a.var_kind), a.target, static_cast<int>(a.index.kind), a.index.fixed};
}

Expr Negate(Expr e) {
  if (e.op == Op::kTrue) return Const(false);
  if (e.op == Op::kFalse) return Const(true);
  if (e.op == Op::kNot) return std::move(e.kids[0]);
  if (e.op == Op::kAtom) {
    e.not_equal = !e.not_equal;
    return e;
  }
  return Unary(Op::kNot, std::move(e));
}

// Builds a conjunction (kAnd) or disjunction (kOr) of already normalised operands: constants
// absorbed, nested chains flattened, atoms over one variable combined as sets of values.
Expr Chain(Op op, std::vector<Expr> items, const ValueNames& values) {
  const bool is_and = op == Op::kAnd;
  std::vector<Expr> flat;
  for (auto& it : items) {
    if (it.op == op) {
      std::vector<const Expr*> parts;
      Flatten(it, op, parts);
      for (const Expr* p : parts) flat.push_back(*p);
    } else {
      flat.push_back(std::move(it));
    }
  }
  // Atoms per variable: the set of values they allow (and) or cover (or).
  std::map<VarKey, std::pair<std::size_t, std::set<int>>> sets;  // first position, values
  std::map<VarKey, const std::vector<std::string>*> names_of;
  std::vector<Expr> rest;
  std::vector<std::pair<std::size_t, VarKey>> order;
  for (auto& it : flat) {
    if (it.op == (is_and ? Op::kTrue : Op::kFalse)) continue;
    if (it.op == (is_and ? Op::kFalse : Op::kTrue)) return Const(!is_and);
    const std::vector<std::string>* names =
        Resolved(it) && values ? values(it.var_kind, it.target) : nullptr;
    const int n = names ? static_cast<int>(names->size()) : 0;
    if (n <= 0) {
      rest.push_back(std::move(it));
      continue;
    }
    VarKey k = KeyOf(it);
    std::set<int> allowed;
    for (int v = 0; v < n; ++v)
      if ((v == it.value_code) != it.not_equal) allowed.insert(v);
    auto found = sets.find(k);
    if (found == sets.end()) {
      sets[k] = {rest.size(), allowed};
      names_of[k] = names;
      order.emplace_back(rest.size(), k);
      Expr placeholder = it;
      rest.push_back(std::move(placeholder));
      continue;
    }
    std::set<int> merged;
    for (int v = 0; v < n; ++v) {
      const bool in_a = found->second.second.count(v) > 0, in_b = allowed.count(v) > 0;
      if (is_and ? (in_a && in_b) : (in_a || in_b)) merged.insert(v);
    }
    found->second.second = std::move(merged);
  }
  // Rewrite each variable's atoms as one atom where the set allows it.
  std::vector<Expr> out;
  std::map<std::size_t, VarKey> at;
  for (auto& [pos, k] : order) at[pos] = k;
  for (std::size_t i = 0; i < rest.size(); ++i) {
    auto a = at.find(i);
    if (a == at.end()) {
      out.push_back(std::move(rest[i]));
      continue;
    }
    const std::set<int>& s = sets[a->second].second;
    const std::vector<std::string>& names = *names_of[a->second];
    const int n = static_cast<int>(names.size());
    auto named = [&](Expr p) {
      p.value = names[p.value_code];
      return p;
    };
    if (s.empty()) {
      if (is_and) return Const(false);
      continue;  // nothing covered: false in a disjunction
    }
    if (static_cast<int>(s.size()) == n) {
      if (!is_and) return Const(true);
      continue;  // everything allowed: true in a conjunction
    }
    Expr atom = rest[i];
    if (s.size() == 1) {
      atom.not_equal = false;
      atom.value_code = *s.begin();
      out.push_back(named(std::move(atom)));
    } else if (static_cast<int>(s.size()) == n - 1) {
      int missing = 0;
      while (s.count(missing)) ++missing;
      atom.not_equal = true;
      atom.value_code = missing;
      out.push_back(named(std::move(atom)));
    } else {
      // Several values: a conjunction excludes the values not allowed, a disjunction lists the
      // values covered.
      std::vector<Expr> parts;
      for (int v = 0; v < n; ++v) {
        if ((s.count(v) > 0) == is_and) continue;
        Expr p = atom;
        p.value_code = v;
        p.not_equal = is_and;
        parts.push_back(std::move(p));
      }
      for (auto& p : parts) out.push_back(named(std::move(p)));
    }
  }
  if (out.empty()) return Const(is_and);
  Expr acc = std::move(out[0]);
  for (std::size_t i = 1; i < out.size(); ++i) acc = Binary(op, std::move(acc), std::move(out[i]));
  return acc;
}

}  // namespace

ExprInfo InfoOf(const Expr& e) {
  ExprInfo info;
  std::function<void(const Expr&)> walk = [&](const Expr& x) {
    for (const auto& k : x.kids) walk(k);
    if (x.op != Op::kAtom) return;
    switch (x.var_kind) {
      case VarKind::kLocation: info.locations_read.insert(x.target); break;
      case VarKind::kCommand: info.commands_read.insert(x.target); break;
      case VarKind::kEpisodeState: info.episodes_read.insert(x.target); break;
      case VarKind::kTemporalState: info.temporals_read.insert(x.target); break;
      case VarKind::kUnresolved: return;
    }
    if (x.var_kind != VarKind::kLocation && x.var_kind != VarKind::kCommand) return;
    if (x.index.kind == IndexKind::kI) info.domain_uses_i = true;
    if (x.index.kind == IndexKind::kIPlus1) info.domain_uses_i1 = true;
    if (x.index.kind == IndexKind::kFixed) info.uses_fixed = true;
  };
  walk(e);
  return info;
}

void Flatten(const Expr& e, Expr::Op op, std::vector<const Expr*>& out) {
  if (e.op == op) {
    Flatten(e.kids[0], op, out);
    Flatten(e.kids[1], op, out);
  } else {
    out.push_back(&e);
  }
}

Expr Normalize(const Expr& e, const ValueNames& values) {
  switch (e.op) {
    case Op::kTrue:
    case Op::kFalse:
    case Op::kAtom:
      return e;
    case Op::kNot:
      return Negate(Normalize(e.kids[0], values));
    case Op::kEvery:
    case Op::kAny:  // not expanded (quantify.h): nothing to simplify without the values
      return e;
    case Op::kAnd:
    case Op::kOr: {
      // The whole chain at once: one node at a time copied every normalised sub-chain again
      // (quadratic in the conjuncts of a quantified goal).
      std::vector<const Expr*> parts;
      Flatten(e, e.op, parts);
      std::vector<Expr> items;
      items.reserve(parts.size());
      for (const Expr* p : parts) items.push_back(Normalize(*p, values));
      Expr r = Chain(e.op, std::move(items), values);
      if (r.op != Op::kTrue && r.op != Op::kFalse) r.offset = e.offset;
      return r;
    }
    case Op::kImplies: {
      // a -> b  ==  not a \/ b
      std::vector<Expr> items;
      items.push_back(Negate(Normalize(e.kids[0], values)));
      items.push_back(Normalize(e.kids[1], values));
      return Chain(Op::kOr, std::move(items), values);
    }
    case Op::kIff: {
      Expr a = Normalize(e.kids[0], values), b = Normalize(e.kids[1], values);
      if (IsTrue(a)) return b;
      if (IsTrue(b)) return a;
      if (IsFalse(a)) return Negate(std::move(b));
      if (IsFalse(b)) return Negate(std::move(a));
      return Binary(Op::kIff, std::move(a), std::move(b));
    }
  }
  return e;
}

}  // namespace ctb
