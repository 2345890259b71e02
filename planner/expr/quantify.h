// Expansion of quantifiers (every / any, expr.h) into the plain tree: the encoder, the verifier,
// the analyses and the engines only ever see conjunctions and disjunctions of atoms.
//
// The work an expansion may do is bounded by a node budget, not by the length of the text: a
// short text can ask for millions of nodes (every(a in robot: every(b in robot: ...))). The
// budget is shared by every expression of one document (a state plan, a domain), so many short
// quantified strings cannot add up to more than one budget either.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "planner/expr/expr.h"

namespace ctb {

// Nodes the quantifiers of one document may create (atoms and connectives, all expansions
// together). 1,000 robots with a few atoms each need about 10,000.
constexpr std::size_t kQuantifierNodeBudget = 1 << 15;

struct QuantifierBudget {
  std::size_t left = kQuantifierNodeBudget;
};

// The values of a template's instances ("1", "2", ... or name fragments; the instance is the
// template's name followed by the value), or nullptr when there is no template of that name.
using TemplateValues = std::function<const std::vector<std::string>*(const std::string& name)>;

// The names of the templates, for "did you mean" in an error.
using TemplateNames = std::function<std::vector<std::string>()>;

// Replaces every quantifier of e by the conjunction (every) or disjunction (any) of its body over
// the range's values, with each placeholder "{k}" of a name replaced by k's value; the copies
// are joined as a balanced tree (depth log n) and keep the offsets of the text, and each atom
// inside a quantifier records its variables' values in `binding` (the checker reports one error
// or warning per place in the text, naming them). On error (a template that does not
// exist, a range of more than 100,000 values, the budget used up) returns the offset into the
// text and a message; e is then unspecified.
std::optional<ExprError> ExpandQuantifiers(Expr& e, const TemplateValues& templates,
                                           const TemplateNames& names, QuantifierBudget& budget);

}  // namespace ctb
