#include <vector>

#include "planner/expr/expr.h"

namespace ctb {
namespace {

class Parser {
 public:
  explicit Parser(const std::vector<Token>& toks) : toks_(toks) {}

  std::optional<Expr> ParseAll(ExprError& err) {
    auto e = ParseIff(0);
    if (e && Peek().kind != TokKind::kEnd) {
      Fail(Peek().offset, std::string("expected a connective or the end of the expression, got ") +
                              Describe(Peek()));
      e.reset();
    }
    if (!e) err = err_;
    return e;
  }

 private:
  const Token& Peek() const { return toks_[pos_]; }
  const Token& Next() { return toks_[pos_ < toks_.size() - 1 ? pos_++ : pos_]; }
  bool Accept(TokKind k) {
    if (Peek().kind != k) return false;
    Next();
    return true;
  }
  void Fail(std::size_t offset, std::string message) {
    if (!failed_) err_ = {offset, std::move(message)};
    failed_ = true;
  }
  static std::string Describe(const Token& t) {
    if (t.kind == TokKind::kEnd) return "the end of the expression";
    return "'" + t.text + "'";
  }
  bool Expect(TokKind k, const char* what) {
    if (Accept(k)) return true;
    Fail(Peek().offset, std::string("expected ") + what + ", got " + Describe(Peek()));
    return false;
  }

  static Expr Binary(Expr::Op op, Expr l, Expr r, std::size_t offset) {
    Expr e;
    e.op = op;
    e.offset = offset;
    e.kids.push_back(std::move(l));
    e.kids.push_back(std::move(r));
    return e;
  }

  std::optional<Expr> ParseIff(int depth) {
    auto l = ParseImplies(depth);
    while (l && Peek().kind == TokKind::kIff) {
      std::size_t off = Next().offset;
      auto r = ParseImplies(depth);
      if (!r) return std::nullopt;
      l = Binary(Expr::Op::kIff, std::move(*l), std::move(*r), off);
    }
    return l;
  }

  std::optional<Expr> ParseImplies(int depth) {
    auto l = ParseOr(depth);
    if (l && Peek().kind == TokKind::kImplies) {
      std::size_t off = Next().offset;
      if (depth + 1 > kMaxExprDepth) {
        Fail(off, "expression nested too deeply");
        return std::nullopt;
      }
      auto r = ParseImplies(depth + 1);
      if (!r) return std::nullopt;
      return Binary(Expr::Op::kImplies, std::move(*l), std::move(*r), off);
    }
    return l;
  }

  std::optional<Expr> ParseOr(int depth) {
    auto l = ParseAnd(depth);
    while (l && Peek().kind == TokKind::kOr) {
      std::size_t off = Next().offset;
      auto r = ParseAnd(depth);
      if (!r) return std::nullopt;
      l = Binary(Expr::Op::kOr, std::move(*l), std::move(*r), off);
    }
    return l;
  }

  std::optional<Expr> ParseAnd(int depth) {
    auto l = ParseUnary(depth);
    while (l && Peek().kind == TokKind::kAnd) {
      std::size_t off = Next().offset;
      auto r = ParseUnary(depth);
      if (!r) return std::nullopt;
      l = Binary(Expr::Op::kAnd, std::move(*l), std::move(*r), off);
    }
    return l;
  }

  std::optional<Expr> ParseUnary(int depth) {
    if (depth > kMaxExprDepth) {
      Fail(Peek().offset, "expression nested too deeply");
      return std::nullopt;
    }
    if (Peek().kind == TokKind::kNot) {
      std::size_t off = Next().offset;
      auto k = ParseUnary(depth + 1);
      if (!k) return std::nullopt;
      Expr e;
      e.op = Expr::Op::kNot;
      e.offset = off;
      e.kids.push_back(std::move(*k));
      return e;
    }
    return ParsePrimary(depth);
  }

  std::optional<Expr> ParsePrimary(int depth) {
    const Token& t = Peek();
    Expr e;
    e.offset = t.offset;
    switch (t.kind) {
      case TokKind::kTrue: Next(); e.op = Expr::Op::kTrue; return e;
      case TokKind::kFalse: Next(); e.op = Expr::Op::kFalse; return e;
      case TokKind::kLParen: {
        Next();
        auto inner = ParseIff(depth + 1);
        if (!inner || !Expect(TokKind::kRParen, "')'")) return std::nullopt;
        return inner;
      }
      case TokKind::kIdent:
        if ((t.text == "every" || t.text == "any") && toks_[pos_ + 1].kind == TokKind::kLParen)
          return ParseQuantifier(depth);
        return ParseAtom();
      default:
        Fail(t.offset, "expected a comparison such as 'compl[i]==compOn', 'true', 'false', "
                       "'not' or '(', got " + Describe(t));
        return std::nullopt;
    }
  }

  bool ParseIndex(Index& idx) {
    if (!Expect(TokKind::kLBracket, "'['")) return false;
    const Token& t = Peek();
    idx.offset = t.offset;
    if (t.kind == TokKind::kIdent && t.text == "i") {
      Next();
      if (Accept(TokKind::kPlus)) {
        const Token& one = Peek();
        if (one.kind != TokKind::kInt || one.text != "1") {
          Fail(one.offset, "expected '1' after 'i+' (an index is i, i+1 or a stage number), got " +
                               Describe(one));
          return false;
        }
        Next();
        idx.kind = IndexKind::kIPlus1;
      } else {
        idx.kind = IndexKind::kI;
      }
    } else if (t.kind == TokKind::kInt) {
      Next();
      idx.kind = IndexKind::kFixed;
      idx.fixed = std::stoi(t.text);
    } else {
      Fail(t.offset, "expected an index: i, i+1 or a stage number, got " + Describe(t));
      return false;
    }
    return Expect(TokKind::kRBracket, "']'");
  }

  bool ParseOp(Expr& e) {
    if (Accept(TokKind::kEq)) return true;
    if (Accept(TokKind::kNe)) {
      e.not_equal = true;
      return true;
    }
    Fail(Peek().offset, "expected '==' or '!=', got " + Describe(Peek()));
    return false;
  }

  // every(k in robot: BODY), any(k in 1..4: BODY).
  std::optional<Expr> ParseQuantifier(int depth) {
    Expr e;
    const Token& head = Next();
    e.op = head.text == "every" ? Expr::Op::kEvery : Expr::Op::kAny;
    e.offset = head.offset;
    const std::string form = head.text + "(VAR in RANGE: CONDITION)";
    if (depth + 1 > kMaxExprDepth) {
      Fail(head.offset, "expression nested too deeply");
      return std::nullopt;
    }
    Next();  // '('
    const Token& var = Peek();
    if (var.kind != TokKind::kIdent || var.text.find('{') != std::string::npos) {
      Fail(var.offset, "expected the variable of " + form + ", got " + Describe(var));
      return std::nullopt;
    }
    if (var.text == "i" || var.text == "every" || var.text == "any" || var.text == "in") {
      Fail(var.offset, "'" + var.text + "' cannot be a quantifier's variable");
      return std::nullopt;
    }
    for (const auto& b : bound_)
      if (b == var.text) {
        Fail(var.offset, "'" + var.text + "' is already bound by a quantifier around this one");
        return std::nullopt;
      }
    Next();
    e.var = var.text;
    e.var_offset = var.offset;
    if (Peek().kind != TokKind::kIdent || Peek().text != "in") {
      Fail(Peek().offset, "expected 'in' in " + form + ", got " + Describe(Peek()));
      return std::nullopt;
    }
    Next();
    const Token& range = Peek();
    e.range_offset = range.offset;
    if (range.kind == TokKind::kIdent && range.text.find('{') == std::string::npos) {
      Next();
      e.range = range.text;
    } else if (range.kind == TokKind::kInt) {
      Next();
      e.range_lo = std::stoi(range.text);
      if (!Expect(TokKind::kDotDot, "'..' in a range A..B")) return std::nullopt;
      const Token& hi = Peek();
      if (hi.kind != TokKind::kInt) {
        Fail(hi.offset, "expected the integer that ends the range, got " + Describe(hi));
        return std::nullopt;
      }
      Next();
      e.range_hi = std::stoi(hi.text);
    } else {
      Fail(range.offset, "expected a range: a template's name (every(k in robot: ...)) or "
                         "integers A..B, got " + Describe(range));
      return std::nullopt;
    }
    if (!Expect(TokKind::kColon, "':' after the range")) return std::nullopt;
    bound_.push_back(e.var);
    auto body = ParseIff(depth + 1);
    bound_.pop_back();
    if (!body || !Expect(TokKind::kRParen, "')' closing the quantifier")) return std::nullopt;
    e.kids.push_back(std::move(*body));
    return e;
  }

  // Every placeholder "{k}" of a name must be bound by a quantifier around it.
  bool CheckPlaceholders(const Token& t) {
    for (std::size_t open = t.text.find('{'); open != std::string::npos;
         open = t.text.find('{', open + 1)) {
      const std::size_t close = t.text.find('}', open);
      const std::string name = t.text.substr(open + 1, close - open - 1);
      bool known = false;
      for (const auto& b : bound_) known = known || b == name;
      if (!known) {
        Fail(t.offset + open, bound_.empty()
                                  ? "placeholder '{" + name + "}' outside a quantifier (write "
                                    "every(" + name + " in TEMPLATE: ...) around it)"
                                  : "placeholder '{" + name + "}' names no quantifier's variable "
                                    "here");
        return false;
      }
    }
    return true;
  }

  std::optional<Expr> ParseAtom() {
    Expr e;
    e.op = Expr::Op::kAtom;
    const Token& first = Next();
    e.offset = first.offset;
    if (Peek().kind == TokKind::kLBracket) {  // var[index] op value
      e.var = first.text;
      e.var_offset = first.offset;
      if (!ParseIndex(e.index) || !ParseOp(e)) return std::nullopt;
      const Token& v = Peek();
      if (v.kind != TokKind::kIdent) {
        Fail(v.offset, "expected a value name, got " + Describe(v));
        return std::nullopt;
      }
      Next();
      if (!CheckPlaceholders(first) || !CheckPlaceholders(v)) return std::nullopt;
      e.value = v.text;
      e.value_offset = v.offset;
      return e;
    }
    // value op var[index]
    e.value = first.text;
    e.value_offset = first.offset;
    if (Peek().kind != TokKind::kEq && Peek().kind != TokKind::kNe) {
      const bool quantifier_like = Peek().kind == TokKind::kLParen &&
                                   (first.text == "forall" || first.text == "exists" ||
                                    first.text == "all" || first.text == "some");
      Fail(Peek().offset, "expected '[' after variable '" + first.text + "', got " +
                              Describe(Peek()) +
                              (quantifier_like ? " (a quantifier is written every(k in TEMPLATE: "
                                                 "...) or any(k in TEMPLATE: ...))"
                                               : ""));
      return std::nullopt;
    }
    if (!ParseOp(e)) return std::nullopt;
    const Token& var = Peek();
    if (var.kind != TokKind::kIdent) {
      Fail(var.offset, "expected a variable name, got " + Describe(var));
      return std::nullopt;
    }
    Next();
    if (!CheckPlaceholders(first) || !CheckPlaceholders(var)) return std::nullopt;
    e.var = var.text;
    e.var_offset = var.offset;
    if (!ParseIndex(e.index)) return std::nullopt;
    return e;
  }

  const std::vector<Token>& toks_;
  std::vector<std::string> bound_;  // the variables of the quantifiers around the current point
  std::size_t pos_ = 0;
  bool failed_ = false;
  ExprError err_;
};

}  // namespace

bool HasQuantifier(const Expr& e) {
  if (e.op == Expr::Op::kEvery || e.op == Expr::Op::kAny) return true;
  for (const auto& k : e.kids)
    if (HasQuantifier(k)) return true;
  return false;
}

std::optional<Expr> Parse(std::string_view text, ExprError& err, std::size_t max_length) {
  std::vector<Token> toks;
  if (auto lex_err = Lex(text, toks, max_length)) {
    err = *lex_err;
    return std::nullopt;
  }
  Parser p(toks);
  return p.ParseAll(err);
}

}  // namespace ctb
