#include "planner/expr/expr_print.h"

namespace ctb {

std::string PrintMiniZinc(const Expr& e, const VarPrinter& var) {
  switch (e.op) {
    case Expr::Op::kTrue: return "true";
    case Expr::Op::kFalse: return "false";
    case Expr::Op::kAtom:
      return "(" + var(e) + (e.not_equal ? " != " : " = ") + std::to_string(e.value_code) + ")";
    case Expr::Op::kNot: return "(not " + PrintMiniZinc(e.kids[0], var) + ")";
    case Expr::Op::kAnd:
    case Expr::Op::kOr:
    case Expr::Op::kImplies:
    case Expr::Op::kIff: {
      const char* op = e.op == Expr::Op::kAnd       ? " /\\ "
                       : e.op == Expr::Op::kOr      ? " \\/ "
                       : e.op == Expr::Op::kImplies ? " -> "
                                                    : " <-> ";
      return "(" + PrintMiniZinc(e.kids[0], var) + op + PrintMiniZinc(e.kids[1], var) + ")";
    }
    case Expr::Op::kEvery:
    case Expr::Op::kAny: break;  // expanded before a tree is checked (quantify.h)
  }
  return "false";
}

bool Evaluate(const Expr& e, const std::function<int(const Expr& atom)>& value_of) {
  switch (e.op) {
    case Expr::Op::kTrue: return true;
    case Expr::Op::kFalse: return false;
    case Expr::Op::kAtom: return (value_of(e) == e.value_code) != e.not_equal;
    case Expr::Op::kNot: return !Evaluate(e.kids[0], value_of);
    case Expr::Op::kAnd: return Evaluate(e.kids[0], value_of) && Evaluate(e.kids[1], value_of);
    case Expr::Op::kOr: return Evaluate(e.kids[0], value_of) || Evaluate(e.kids[1], value_of);
    case Expr::Op::kImplies: return !Evaluate(e.kids[0], value_of) || Evaluate(e.kids[1], value_of);
    case Expr::Op::kIff: return Evaluate(e.kids[0], value_of) == Evaluate(e.kids[1], value_of);
    case Expr::Op::kEvery:
    case Expr::Op::kAny: break;  // expanded before a tree is checked (quantify.h)
  }
  return false;
}

}  // namespace ctb

namespace ctb {

std::string PrintSource(const Expr& e) {
  switch (e.op) {
    case Expr::Op::kTrue: return "true";
    case Expr::Op::kFalse: return "false";
    case Expr::Op::kAtom: {
      std::string idx = e.index.kind == IndexKind::kI       ? "i"
                        : e.index.kind == IndexKind::kIPlus1 ? "i+1"
                                                             : std::to_string(e.index.fixed);
      return e.var + "[" + idx + "]" + (e.not_equal ? "!=" : "==") + e.value;
    }
    case Expr::Op::kNot: return "not (" + PrintSource(e.kids[0]) + ")";
    case Expr::Op::kEvery:
    case Expr::Op::kAny: {
      const std::string range = !e.range.empty() ? e.range
                                                 : std::to_string(e.range_lo) + ".." +
                                                       std::to_string(e.range_hi);
      return std::string(e.op == Expr::Op::kEvery ? "every(" : "any(") + e.var + " in " + range +
             ": " + PrintSource(e.kids[0]) + ")";
    }
    default: {
      const char* op = e.op == Expr::Op::kAnd       ? " /\\ "
                       : e.op == Expr::Op::kOr      ? " \\/ "
                       : e.op == Expr::Op::kImplies ? " -> "
                                                    : " <-> ";
      return "(" + PrintSource(e.kids[0]) + op + PrintSource(e.kids[1]) + ")";
    }
  }
}

}  // namespace ctb
