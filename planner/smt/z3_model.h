// Internal to planner/smt: the z3 terms of one model and the builders that add its constraints
// (one file per constraint kind, as in planner/encode). Not a public header.
#pragma once

#include <z3++.h>

#include <optional>
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
using Exprs3 = std::vector<Exprs2>;

// An index in 0..H (an event number) in order encoding: gt[k] <=> value > k, k = 0..H-1, with
// gt[k+1] -> gt[k]. Comparisons with constants are literals, which suits z3's SAT core.
struct OrderVar {
  z3::context* z = nullptr;
  Exprs gt;
  z3::expr Gt(int k) const;  // value > k: true for k < 0, false for k >= H
  z3::expr Le(int k) const { return !Gt(k); }
  z3::expr Eq(int k) const { return Gt(k - 1) && !Gt(k); }
};

// Assumption literals of the state plan's parts (z3_core.h): each part's constraints hold only
// under its literal, so a check under a subset of them solves the plan with only those parts
// (the others dropped as the explanation drops them: a goal or maintenance constraint becomes
// true, an episode or temporal constraint goes with its endpoints in shared events).
struct PartLiterals {
  z3::expr goal, maintenance;
  Exprs episodes, temporals, events;
};

// The model's variables. Times (e, N) are integers, so time constraints are differences of two
// integers; the discrete choices are Booleans: one per location, transition and command of each
// automaton at each stage or event (the MiniZinc model's L, X and U, one-hot), and the event
// indices (g, EP_S, ...) in order encoding. Automata and state-plan parts are 0-based.
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

  Exprs e;           // e[0..H]
  Exprs2 N;          // [a][0..H] entry times
  Exprs3 loc;        // [a][0..H][l]: L[a,k] = l
  Exprs3 fire;       // [a][0..H-1][i]: X[a,k] is automaton a's transition i
  Exprs3 cmd;        // [a][0..H][c]: U[a,k] = c (0: the no-op)
  Exprs2 idle;       // [a][0..H-1]: X[a,k] = 0
  OrderVar g;
  std::vector<OrderVar> ep_s, ep_e, tc_1, tc_2, tc_a, tc_b;
  z3::expr cost, makespan, objective;
  z3::expr_vector constraints;
  // Set before AddStatePlan for a model with switchable parts; unset: every part holds.
  std::optional<PartLiterals> parts;
  // While set (AddStatePlan, per part), Add() adds its constraint under this literal.
  std::optional<z3::expr> gate;

  void Add(const z3::expr& c) { constraints.push_back(gate ? z3::implies(*gate, c) : c); }
  z3::expr Int(const std::string& name);
  z3::expr Bool(const std::string& name);
  OrderVar Order(const std::string& name);
  z3::expr Val(long v) { return z.int_val(static_cast<int64_t>(v)); }
  z3::expr True() { return z.bool_val(true); }
  z3::expr False() { return z.bool_val(false); }
  z3::expr LocIs(int a, int k, int l) const;
  z3::expr CmdIs(int a, int k, int c) const;
  // A fresh integer equal to arr[idx].
  z3::expr At(const Exprs& arr, const OrderVar& idx, const std::string& name);
  // The accepting automata's states before event k (0 at k = 0) equal `code`, as EPSTATE /
  // TCSTATE = (k-1 >= start) + (k-1 >= end).
  z3::expr EpStateIs(int p, int k, int code);
  z3::expr TcStateIs(int q, int k, int code);
  // Exactly one (at most one when `exactly` is false) of xs holds.
  void One(const Exprs& xs, bool exactly);
};

inline bool IsTrueCondition(const Condition& c) { return c.expr.op == Expr::Op::kTrue; }

// The condition e at index k (0..H), following the contract's "when a condition holds" rules
// exactly as planner/encode's PrintCondition: a change condition is false at k = 0.
z3::expr CondAt(Model& m, const Expr& e, const ExprInfo& info, CondMode mode, int k);

void AddAutomata(Model& m);
void AddStatePlan(Model& m);
void AddObjective(Model& m);

}  // namespace ctb::smt
