// Prints a checked expression as MiniZinc. Only resolved codes and the text returned by the
// caller's variable printer appear in the output: no name from the input string is ever copied.
#pragma once

#include <functional>
#include <string>

#include "planner/expr/expr.h"

namespace ctb {

// Returns the MiniZinc term for the variable of a checked atom (e.g. "L[2,k-1]"). It must
// produce text from the atom's resolved fields (var_kind, target, index), never from atom.var.
using VarPrinter = std::function<std::string(const Expr& atom)>;

// Fully parenthesized MiniZinc text; atoms become "(<term> = <code>)" or "(<term> != <code>)".
std::string PrintMiniZinc(const Expr& e, const VarPrinter& var);

// Evaluates a checked expression given the value of each atom's variable.
bool Evaluate(const Expr& e, const std::function<int(const Expr& atom)>& value_of);

}  // namespace ctb

namespace ctb {

// Prints a parsed expression back in the expression language (names as written), fully
// parenthesized. Parsing the result gives the same tree.
std::string PrintSource(const Expr& e);

}  // namespace ctb
