// Internal to planner/smt: the z3 terms of one model and the builders that add its constraints
// (one file per constraint kind, as in planner/encode). Not a public header.
#pragma once

#include <z3++.h>

#include <vector>

#include "planner/encode/encoder.h"

namespace ctb::smt {

// How the stage of a domain variable is chosen when a condition is built (as PrintCondition).
enum class CondMode {
  kEvent,  // at event k: [i] -> stage k-1, [i+1] -> stage k (change); both -> k (state)
  kStage,  // on stage k: [i] and [i+1] -> stage k
  kGuard,  // guard on stage k: [i] -> k
};

using Exprs = std::vector<z3::expr>;
using Exprs2 = std::vector<Exprs>;

// The model's variables, named as in the MiniZinc text; automata and state-plan parts are
// 0-based here (the MiniZinc arrays are 1-based).
struct Model {
  Model(z3::context& ctx, const ModelSpec& spec);

  z3::context& z;
  const Domain& d;
  const StatePlan& sp;
  const ProblemInfo& info;
  const EncodeOptions& opts;
  const int H;
  const long T;  // time bound, ticks
  long declared = 0;

  Exprs e;               // e[0..H]
  Exprs2 L, X, N, U;     // [a][0..H] (X: [a][0..H-1])
  z3::expr g;
  Exprs ep_s, ep_e, tc_1, tc_2, tc_a, tc_b;
  z3::expr cost, makespan, objective;
  z3::expr_vector constraints;

  void Add(const z3::expr& c) { constraints.push_back(c); }
  z3::expr Int(const std::string& name);
  z3::expr Val(long v) { return z.int_val(static_cast<int64_t>(v)); }
  // A fresh integer equal to arr[idx] for a variable index idx in 0..arr.size()-1.
  z3::expr At(const Exprs& arr, const z3::expr& idx, const std::string& name);
  // The accepting automata's states before event k (0 at k = 0), as EPSTATE / TCSTATE.
  z3::expr EpState(int p, int k);
  z3::expr TcState(int q, int k);
};

inline bool IsTrueCondition(const Condition& c) { return c.expr.op == Expr::Op::kTrue; }

// The condition e at index k (0..H), following the contract's "when a condition holds" rules
// exactly as planner/encode's PrintCondition: a change condition is false at k = 0.
z3::expr CondAt(Model& m, const Expr& e, const ExprInfo& info, CondMode mode, int k);

void AddAutomata(Model& m);
void AddStatePlan(Model& m);
void AddObjective(Model& m);

}  // namespace ctb::smt
