// Fuzz target: the expression language (planner/expr, model/expr_check.h). The input is one
// guard or condition as a client writes it. Checked: parsing never crashes; a parsed tree prints
// back (PrintSource) to text that parses to the same tree; checked against the presentation
// domain as a condition and as a guard, errors carry a pointer and an offset inside the text;
// the normalised tree has the raw tree's truth value on sampled assignments.
#include <cstdint>
#include <cstring>

#include "planner/expr/expr.h"
#include "planner/expr/expr_print.h"
#include "planner/expr/normalize.h"
#include "planner/model/expr_check.h"
#include "tests/fuzz/fuzz_util.h"

namespace {

using namespace ctb;

// A value for every variable, drawn from (kind, target, index) and a seed; within the variable's
// value range when it is known.
int Sample(const Expr& atom, const ValueNames& names, unsigned seed) {
  unsigned h = seed * 2654435761u;
  h ^= static_cast<unsigned>(atom.var_kind) * 40503u + static_cast<unsigned>(atom.target) * 97u;
  h ^= static_cast<unsigned>(atom.index.kind) * 7919u + static_cast<unsigned>(atom.index.fixed);
  h *= 2246822519u;
  h ^= h >> 13;
  const std::vector<std::string>* v = names(atom.var_kind, atom.target);
  const unsigned n = v && !v->empty() ? static_cast<unsigned>(v->size()) : 4u;
  return static_cast<int>(h % n);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const Domain dom = fuzz::LoadShippedDomain("config/domains/presentation.json");
  const std::string text(fuzz::Text(data, size));

  ExprError err;
  std::optional<Expr> e = Parse(text, err);
  if (!e) {
    if (err.message.empty()) fuzz::Fail("a parse error without a message");
    if (err.offset > text.size() && err.offset != kMaxExprLength)
      fuzz::Fail("a parse error's offset lies past the text");
    return 0;
  }
  // Round trip through the printer.
  const std::string printed = PrintSource(*e);
  ExprError err2;
  std::optional<Expr> again = Parse(printed, err2);
  if (!again) {
    // The printer parenthesises every connective: a long flat chain can come back deeper than
    // kMaxExprDepth or longer than kMaxExprLength; anything else is a finding.
    const bool limit = printed.size() > kMaxExprLength ||
                       err2.message.find("deep") != std::string::npos ||
                       err2.message.find("nest") != std::string::npos;
    if (!limit) fuzz::Fail("PrintSource gave text that does not parse");
  } else if (PrintSource(*again) != printed) {
    fuzz::Fail("PrintSource(Parse(PrintSource(e))) differs from PrintSource(e)");
  }

  // Names resolved against a domain, as a condition (with episodes and temporals in scope) and
  // as a guard.
  Scope scope{&dom, {"ProjectorOn", "e1"}, {"first60", "t1"}};
  DomainValueNames value_names(dom);
  const ValueNames names = value_names.Function();
  for (ExprContext ctx : {ExprContext::kCondition, ExprContext::kGuard}) {
    Diagnostics diags;
    ExprInfo info;
    std::optional<Expr> checked = ParseChecked(text, scope, ctx, "/x", diags, &info);
    fuzz::CheckDiagnostics(diags);
    if (!checked) {
      if (diags.ok()) fuzz::Fail("ParseChecked failed without an error");
      for (const auto& d : diags.errors())
        if (d.offset && *d.offset > text.size()) fuzz::Fail("a check error's offset lies past the text");
      continue;
    }
    const Expr norm = Normalize(*checked, names);
    (void)InfoOf(norm);
    (void)PrintMiniZinc(norm, [](const Expr& a) {
      return "v" + std::to_string(static_cast<int>(a.var_kind)) + "_" + std::to_string(a.target);
    });
    for (unsigned seed = 0; seed < 8; ++seed) {
      auto value_of = [&](const Expr& atom) { return Sample(atom, names, seed); };
      if (Evaluate(*checked, value_of) != Evaluate(norm, value_of))
        fuzz::Fail("Normalize changed the truth value of an expression");
    }
  }
  return 0;
}
