#include "planner/analyze/clauses.h"

#include <algorithm>

namespace ctb {

namespace {

// x or y: a clause of each, joined; true (empty) when either side is.
Clauses Disjoin(const Clauses& x, const Clauses& y) {
  Clauses out;
  if (x.empty() || y.empty()) return out;
  for (const Clause& a : x)
    for (const Clause& b : y) {
      Clause both = a;
      for (const LocationAtom& t : b)
        if (std::find(both.begin(), both.end(), t) == both.end()) both.push_back(t);
      out.push_back(std::move(both));
      if (out.size() >= kMaxClauses) return out;
    }
  return out;
}

}  // namespace

Clauses ToClauses(const Expr& e) {
  switch (e.op) {
    case Expr::Op::kFalse: return {Clause{}};
    case Expr::Op::kAtom:
      if (e.var_kind == VarKind::kLocation && !e.not_equal && e.index.kind != IndexKind::kFixed)
        return {Clause{{e.target, e.value_code}}};
      return {};
    case Expr::Op::kAnd: {
      Clauses out = ToClauses(e.kids[0]);
      for (Clause& c : ToClauses(e.kids[1])) {
        if (out.size() >= kMaxConjunctionClauses) break;
        out.push_back(std::move(c));
      }
      return out;
    }
    case Expr::Op::kOr: return Disjoin(ToClauses(e.kids[0]), ToClauses(e.kids[1]));
    default: return {};
  }
}

}  // namespace ctb
