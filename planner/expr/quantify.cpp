#include "planner/expr/quantify.h"

#include <map>
#include <utility>

namespace ctb {

namespace {

constexpr long kMaxRangeValues = 100000;

using Env = std::vector<std::pair<std::string, std::string>>;  // variable -> value, innermost last

class Expander {
 public:
  Expander(const TemplateValues& templates, const TemplateNames& names, QuantifierBudget& budget)
      : templates_(templates), names_(names), budget_(budget) {}

  // The expansion of e under env; nullopt once err_ is set.
  std::optional<Expr> Run(const Expr& e, Env& env) {
    if (!Spend()) return std::nullopt;
    switch (e.op) {
      case Expr::Op::kTrue:
      case Expr::Op::kFalse: return e;
      case Expr::Op::kAtom: return Atom(e, env);
      case Expr::Op::kEvery:
      case Expr::Op::kAny: return Quantifier(e, env);
      default: break;
    }
    Expr out;
    out.op = e.op;
    out.offset = e.offset;
    for (const auto& k : e.kids) {
      auto x = Run(k, env);
      if (!x) return std::nullopt;
      out.kids.push_back(std::move(*x));
    }
    return out;
  }

  ExprError error() const { return err_; }

 private:
  // Counts one node; at the end of the budget the error points at the quantifier being
  // expanded.
  bool Spend() {
    if (budget_.left == 0) {
      if (!failed_)
        err_ = {quantifier_offset_, "the quantifiers expand to more than " +
                            std::to_string(kQuantifierNodeBudget) +
                            " nodes (the limit of one document); say it with fewer or "
                            "smaller quantifiers"};
      failed_ = true;
      return false;
    }
    --budget_.left;
    return true;
  }

  static std::string Substitute(const std::string& s, const Env& env) {
    if (s.find('{') == std::string::npos) return s;
    std::string out;
    std::size_t pos = 0;
    for (std::size_t open = s.find('{'); open != std::string::npos; open = s.find('{', pos)) {
      const std::size_t close = s.find('}', open);
      const std::string name = s.substr(open + 1, close - open - 1);
      out += s.substr(pos, open - pos);
      for (auto it = env.rbegin(); it != env.rend(); ++it)
        if (it->first == name) {
          out += it->second;
          break;
        }
      pos = close + 1;
    }
    return out + s.substr(pos);
  }

  Expr Atom(const Expr& e, const Env& env) {
    Expr out = e;
    out.var = Substitute(e.var, env);
    out.value = Substitute(e.value, env);
    for (const auto& [k, v] : env) out.binding += (out.binding.empty() ? "" : ", ") + k + "=" + v;
    return out;
  }

  std::optional<Expr> Quantifier(const Expr& e, Env& env) {
    const bool every = e.op == Expr::Op::kEvery;
    std::vector<std::string> ints;
    const std::vector<std::string>* values = &ints;
    if (!e.range.empty()) {
      values = templates_ ? templates_(e.range) : nullptr;
      if (!values) {
        std::string known;
        for (const auto& n : names_ ? names_() : std::vector<std::string>{})
          known += (known.empty() ? "" : ", ") + n;
        return Fail(e.range_offset, "unknown template '" + e.range + "' (" +
                                        (known.empty() ? std::string("the domain has no templates")
                                                       : "templates: " + known) +
                                        "); a range is a template's name or integers A..B");
      }
    } else {
      if (static_cast<long>(e.range_hi) - e.range_lo + 1 > kMaxRangeValues)
        return Fail(e.range_offset, "a range has at most " + std::to_string(kMaxRangeValues) +
                                        " values");
      for (long v = e.range_lo; v <= e.range_hi; ++v) ints.push_back(std::to_string(v));
    }
    if (values->empty()) {
      Expr c;
      c.op = every ? Expr::Op::kTrue : Expr::Op::kFalse;
      c.offset = e.offset;
      return c;
    }
    std::vector<Expr> parts;
    parts.reserve(values->size());
    const std::size_t outer = quantifier_offset_;
    quantifier_offset_ = e.offset;
    for (const std::string& v : *values) {
      env.emplace_back(e.var, v);
      auto x = Run(e.kids[0], env);
      env.pop_back();
      if (!x) return std::nullopt;
      parts.push_back(std::move(*x));
    }
    auto joined = Join(every ? Expr::Op::kAnd : Expr::Op::kOr, parts, 0, parts.size(), e.offset);
    quantifier_offset_ = outer;
    return joined;
  }

  // parts[lo, hi) joined by op as a balanced tree.
  std::optional<Expr> Join(Expr::Op op, std::vector<Expr>& parts, std::size_t lo, std::size_t hi,
                           std::size_t offset) {
    if (hi - lo == 1) return std::move(parts[lo]);
    if (!Spend()) return std::nullopt;
    const std::size_t mid = lo + (hi - lo) / 2;
    auto l = Join(op, parts, lo, mid, offset);
    if (!l) return std::nullopt;
    auto r = Join(op, parts, mid, hi, offset);
    if (!r) return std::nullopt;
    Expr out;
    out.op = op;
    out.offset = offset;
    out.kids.push_back(std::move(*l));
    out.kids.push_back(std::move(*r));
    return out;
  }

  std::nullopt_t Fail(std::size_t offset, std::string message) {
    if (!failed_) err_ = {offset, std::move(message)};
    failed_ = true;
    return std::nullopt;
  }

  const TemplateValues& templates_;
  const TemplateNames& names_;
  QuantifierBudget& budget_;
  ExprError err_;
  bool failed_ = false;
  std::size_t quantifier_offset_ = 0;  // the innermost quantifier being expanded
};

}  // namespace

std::optional<ExprError> ExpandQuantifiers(Expr& e, const TemplateValues& templates,
                                           const TemplateNames& names, QuantifierBudget& budget) {
  if (!HasQuantifier(e)) return std::nullopt;
  Expander x(templates, names, budget);
  Env env;
  auto out = x.Run(e, env);
  if (!out) return x.error();
  e = std::move(*out);
  return std::nullopt;
}

}  // namespace ctb
