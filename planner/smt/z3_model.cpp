// The model's variables and the condition builder (the z3 counterpart of PrintCondition).
#include "planner/smt/z3_model.h"

#include <algorithm>
#include <string>

namespace ctb::smt {

namespace {

std::string Name(const char* base, std::size_t a, int k) {
  return std::string(base) + "_" + std::to_string(a) + "_" + std::to_string(k);
}

}  // namespace

Model::Model(z3::context& ctx, const ModelSpec& spec)
    : z(ctx), d(*spec.d), sp(*spec.sp), info(*spec.info), opts(spec.opts), H(spec.opts.horizon),
      T(spec.info->TimeBound(spec.opts.horizon)), g(ctx.int_val(0)), cost(ctx.int_val(0)),
      makespan(ctx.int_val(0)), objective(ctx.int_val(0)), constraints(ctx) {
  for (int k = 0; k <= H; ++k) e.push_back(Int("e_" + std::to_string(k)));
  const std::size_t na = d.automata.size();
  L.resize(na);
  X.resize(na);
  N.resize(na);
  U.resize(na);
  for (std::size_t a = 0; a < na; ++a)
    for (int k = 0; k <= H; ++k) {
      L[a].push_back(Int(Name("L", a, k)));
      N[a].push_back(Int(Name("N", a, k)));
      U[a].push_back(Int(Name("U", a, k)));
      if (k < H) X[a].push_back(Int(Name("X", a, k)));
    }
  g = Int("g");
  auto indices = [&](const char* base, std::size_t n, Exprs& out) {
    for (std::size_t i = 0; i < n; ++i) out.push_back(Int(base + std::to_string(i)));
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

z3::expr Model::At(const Exprs& arr, const z3::expr& idx, const std::string& name) {
  z3::expr v = Int(name);
  for (std::size_t k = 0; k < arr.size(); ++k)
    Add(z3::implies(idx == static_cast<int>(k), v == arr[k]));
  return v;
}

// EPSTATE[p,k-1] = bool2int(k-1 >= EP_S[p]) + bool2int(k-1 >= EP_E[p]); 0 at k = 0.
z3::expr Model::EpState(int p, int k) {
  if (k == 0) return z.int_val(0);
  return z3::ite(ep_s[p] <= k - 1, z.int_val(1), z.int_val(0)) +
         z3::ite(ep_e[p] <= k - 1, z.int_val(1), z.int_val(0));
}

z3::expr Model::TcState(int q, int k) {
  if (k == 0) return z.int_val(0);
  return z3::ite(tc_a[q] <= k - 1, z.int_val(1), z.int_val(0)) +
         z3::ite(tc_b[q] <= k - 1, z.int_val(1), z.int_val(0));
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

  z3::expr Term(const Expr& atom) {
    switch (atom.var_kind) {
      case VarKind::kLocation: return m.L[atom.target][Stage(atom.index)];
      case VarKind::kCommand: return m.U[atom.target][Stage(atom.index)];
      case VarKind::kEpisodeState: return m.EpState(atom.target, k);
      case VarKind::kTemporalState: return m.TcState(atom.target, k);
      case VarKind::kUnresolved: break;
    }
    return m.z.int_val(-1);  // unreachable for checked trees; equal to no code
  }

  z3::expr Build(const Expr& e) {
    switch (e.op) {
      case Expr::Op::kTrue: return m.z.bool_val(true);
      case Expr::Op::kFalse: return m.z.bool_val(false);
      case Expr::Op::kAtom: {
        z3::expr eq = Term(e) == e.value_code;
        return e.not_equal ? !eq : eq;
      }
      case Expr::Op::kNot: return !Build(e.kids[0]);
      case Expr::Op::kAnd: return Build(e.kids[0]) && Build(e.kids[1]);
      case Expr::Op::kOr: return Build(e.kids[0]) || Build(e.kids[1]);
      case Expr::Op::kImplies: return z3::implies(Build(e.kids[0]), Build(e.kids[1]));
      case Expr::Op::kIff: return Build(e.kids[0]) == Build(e.kids[1]);
    }
    return m.z.bool_val(false);
  }
};

}  // namespace

z3::expr CondAt(Model& m, const Expr& e, const ExprInfo& info, CondMode mode, int k) {
  const bool change = mode == CondMode::kEvent && info.IsChange();
  if (change && k == 0) return m.z.bool_val(false);
  return CondBuilder{m, change, k}.Build(e);
}

}  // namespace ctb::smt
