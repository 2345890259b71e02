// The model's variables and the condition builder (the z3 counterpart of PrintCondition).
#include "planner/smt/z3_model.h"

#include <algorithm>
#include <string>

namespace ctb::smt {

namespace {

std::string Name(const char* base, std::size_t a, int k, std::size_t i) {
  return std::string(base) + "_" + std::to_string(a) + "_" + std::to_string(k) + "_" +
         std::to_string(i);
}

// EPSTATE / TCSTATE at j = k-1 equal code, from the start and end indices.
z3::expr StateIs(Model& m, const OrderVar& start, const OrderVar& end, int k, int code) {
  if (k == 0) return m.z.bool_val(code == 0);
  const z3::expr b1 = start.Le(k - 1), b2 = end.Le(k - 1);
  switch (code) {
    case 0: return !b1 && !b2;
    case 1: return b1 != b2;
    case 2: return b1 && b2;
    default: return m.False();  // Failed: the sum never reaches 3
  }
}

}  // namespace

z3::expr OrderVar::Gt(int k) const {
  if (k < 0) return z->bool_val(true);
  if (k >= static_cast<int>(gt.size())) return z->bool_val(false);
  return gt[k];
}

Model::Model(z3::context& ctx, const ModelSpec& spec)
    : z(ctx), d(*spec.d), sp(*spec.sp), info(*spec.info), opts(spec.opts), H(spec.opts.horizon),
      T(spec.info->TimeBound(spec.opts.horizon)), cost(ctx.int_val(0)),
      makespan(ctx.int_val(0)), objective(ctx.int_val(0)), constraints(ctx) {
  for (int k = 0; k <= H; ++k) e.push_back(Int("e_" + std::to_string(k)));
  const std::size_t na = d.automata.size();
  N.resize(na);
  loc.resize(na);
  fire.resize(na);
  cmd.resize(na);
  idle.resize(na);
  for (std::size_t a = 0; a < na; ++a) {
    const Automaton& au = d.automata[a];
    for (int k = 0; k <= H; ++k) {
      N[a].push_back(Int("N_" + std::to_string(a) + "_" + std::to_string(k)));
      loc[a].emplace_back();
      for (std::size_t l = 0; l < au.locations.size(); ++l)
        loc[a][k].push_back(Bool(Name("L", a, k, l)));
      cmd[a].emplace_back();
      for (std::size_t c = 0; c <= au.commands.size(); ++c)
        cmd[a][k].push_back(Bool(Name("U", a, k, c)));
      if (k == H) continue;
      fire[a].emplace_back();
      z3::expr_vector any(z);
      for (std::size_t i = 0; i < au.transitions.size(); ++i) {
        fire[a][k].push_back(Bool(Name("X", a, k, i)));
        any.push_back(fire[a][k].back());
      }
      idle[a].push_back(any.empty() ? True() : !z3::mk_or(any));
    }
  }
  g = Order("g");
  auto indices = [&](const char* base, std::size_t n, std::vector<OrderVar>& out) {
    for (std::size_t i = 0; i < n; ++i) out.push_back(Order(base + std::to_string(i)));
  };
  indices("EP_S_", sp.episodes.size(), ep_s);
  indices("EP_E_", sp.episodes.size(), ep_e);
  indices("TC_1_", sp.temporals.size(), tc_1);
  indices("TC_2_", sp.temporals.size(), tc_2);
  indices("TC_A_", sp.temporals.size(), tc_a);
  indices("TC_B_", sp.temporals.size(), tc_b);
}

z3::expr Model::Int(const std::string& name) {
  ++declared;
  return z.int_const(name.c_str());
}

z3::expr Model::Bool(const std::string& name) {
  ++declared;
  return z.bool_const(name.c_str());
}

OrderVar Model::Order(const std::string& name) {
  OrderVar v;
  v.z = &z;
  for (int k = 0; k < H; ++k) v.gt.push_back(Bool(name + "_gt_" + std::to_string(k)));
  for (int k = 0; k + 1 < H; ++k) Add(z3::implies(v.gt[k + 1], v.gt[k]));
  return v;
}

z3::expr Model::LocIs(int a, int k, int l) const {
  if (l < 0 || l >= static_cast<int>(loc[a][k].size())) return z.bool_val(false);
  return loc[a][k][l];
}

z3::expr Model::CmdIs(int a, int k, int c) const {
  if (c < 0 || c >= static_cast<int>(cmd[a][k].size())) return z.bool_val(false);
  return cmd[a][k][c];
}

z3::expr Model::At(const Exprs& arr, const OrderVar& idx, const std::string& name) {
  z3::expr v = Int(name);
  for (std::size_t k = 0; k < arr.size(); ++k)
    Add(z3::implies(idx.Eq(static_cast<int>(k)), v == arr[k]));
  return v;
}

z3::expr Model::EpStateIs(int p, int k, int code) {
  return StateIs(*this, ep_s[p], ep_e[p], k, code);
}

z3::expr Model::TcStateIs(int q, int k, int code) {
  return StateIs(*this, tc_a[q], tc_b[q], k, code);
}

void Model::One(const Exprs& xs, bool exactly) {
  if (exactly) {
    z3::expr_vector v(z);
    for (const auto& x : xs) v.push_back(x);
    Add(v.empty() ? False() : z3::mk_or(v));
  }
  for (std::size_t i = 0; i < xs.size(); ++i)
    for (std::size_t j = i + 1; j < xs.size(); ++j) Add(!xs[i] || !xs[j]);
}

namespace {

struct CondBuilder {
  Model& m;
  bool change;
  int k;

  int Stage(const Index& idx) const {
    if (idx.kind == IndexKind::kFixed) return std::min(idx.fixed, m.H);
    if (change && idx.kind == IndexKind::kI) return k - 1;
    return k;
  }

  z3::expr Atom(const Expr& atom) {
    switch (atom.var_kind) {
      case VarKind::kLocation: return m.LocIs(atom.target, Stage(atom.index), atom.value_code);
      case VarKind::kCommand: return m.CmdIs(atom.target, Stage(atom.index), atom.value_code);
      case VarKind::kEpisodeState: return m.EpStateIs(atom.target, k, atom.value_code);
      case VarKind::kTemporalState: return m.TcStateIs(atom.target, k, atom.value_code);
      case VarKind::kUnresolved: break;
    }
    return m.False();  // unreachable for checked trees
  }

  z3::expr Build(const Expr& e) {
    switch (e.op) {
      case Expr::Op::kTrue: return m.True();
      case Expr::Op::kFalse: return m.False();
      case Expr::Op::kAtom: return e.not_equal ? !Atom(e) : Atom(e);
      case Expr::Op::kNot: return !Build(e.kids[0]);
      case Expr::Op::kAnd: return Build(e.kids[0]) && Build(e.kids[1]);
      case Expr::Op::kOr: return Build(e.kids[0]) || Build(e.kids[1]);
      case Expr::Op::kImplies: return z3::implies(Build(e.kids[0]), Build(e.kids[1]));
      case Expr::Op::kIff: return Build(e.kids[0]) == Build(e.kids[1]);
      case Expr::Op::kEvery:  // quantifiers are expanded at load (quantify.h)
      case Expr::Op::kAny: break;
    }
    return m.False();
  }
};

}  // namespace

z3::expr CondAt(Model& m, const Expr& e, const ExprInfo& info, CondMode mode, int k) {
  const bool change = mode == CondMode::kEvent && info.IsChange();
  if (change && k == 0) return m.False();
  return CondBuilder{m, change, k}.Build(e);
}

}  // namespace ctb::smt
