// Normalisation of a checked expression: the same truth value on every assignment, in a simpler
// form, so that harmless rewritings an LLM writes ("(true) /\ (true)", "not not G", "G \/ false",
// "x==a \/ x!=a") are recognised by the split, the bounds and the encoder alike.
//
// Rules: constant folding of true/false through every connective; double negation; negation of
// an atom (== <-> !=); implication and equivalence with a constant side; atoms over one variable
// (same kind, target and index) in one conjunction or disjunction combined as sets of values:
// an empty set is false, a full set is true, contradictions and tautologies fold. Conjunctions
// and disjunctions come out as left-nested binary chains without constants.
//
// What a condition reads at [i] and [i+1] is not recomputed here: callers keep the original
// classification (change or state), so the normalised tree means exactly what the original did.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "planner/expr/expr.h"
#include "planner/expr/expr_info.h"

namespace ctb {

// The names of the values a variable of this kind and target can take, by code (locations;
// commands with the no-op at code 0; accepting-automaton states); nullptr when unknown (then its
// atoms are never merged).
using ValueNames = std::function<const std::vector<std::string>*(VarKind kind, int target)>;

// Returns the normalised tree. e must be checked (atoms resolved); unresolved atoms are kept as
// they are and never merged.
Expr Normalize(const Expr& e, const ValueNames& values);

// The operands of a chain of `op` (kAnd or kOr), left to right; e itself when it is not one.
void Flatten(const Expr& e, Expr::Op op, std::vector<const Expr*>& out);

// What a checked tree reads (indices and read sets), computed from the tree itself.
ExprInfo InfoOf(const Expr& e);

// True when e is the constant true (false).
inline bool IsTrue(const Expr& e) { return e.op == Expr::Op::kTrue; }
inline bool IsFalse(const Expr& e) { return e.op == Expr::Op::kFalse; }

}  // namespace ctb
