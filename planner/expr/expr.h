// The expression language of guards and state-plan constraints (contract section 4).
//
//   expr    := iff
//   iff     := implies ("<->" implies)*
//   implies := or ("->" implies)?                  (right associative)
//   or      := and ("\/" and)*
//   and     := unary ("/\" unary)*
//   unary   := "not" unary | primary
//   primary := "true" | "false" | "(" expr ")" | quant | atom
//   quant   := ("every" | "any") "(" name "in" range ":" expr ")"
//   range   := name | integer ".." integer         (a template's instances, or integers)
//   atom    := var "[" index "]" op value  |  value op var "[" index "]"
//   op      := "==" | "=" | "!="
//   index   := "i" | "i" "+" "1" | integer
//
// Inside a quantifier's body a name may hold placeholders "{k}" of the variables bound around
// it (robot{k}l[i+1]==rescuedPerson{k}): every(k in robot: B) is the conjunction of B over the
// values of the template robot's instances (robot1 .. robotN: k = 1 .. N), any(...) the
// disjunction; an empty range gives true / false. "every" and "any" are not reserved: they start
// a quantifier only before "(". Quantifiers are expanded before names are checked
// (ExpandQuantifiers, quantify.h), so no checked tree holds one.
//
// Strings are parsed into a tree (Parse), names are resolved against a domain and a state plan
// (Check, in expr_check.h), and MiniZinc text is printed from the checked tree only (Print, in
// expr_print.h). Anything outside the grammar, ';' and quotes included, is rejected with the
// character offset at which it was found.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ctb {

constexpr std::size_t kMaxExprLength = 8192;
constexpr int kMaxExprDepth = 64;

enum class TokKind {
  kIdent, kInt, kLBracket, kRBracket, kLParen, kRParen, kPlus,
  kEq, kNe, kAnd, kOr, kImplies, kIff, kNot, kTrue, kFalse, kColon, kDotDot, kEnd,
};

struct Token {
  TokKind kind;
  std::string text;
  std::size_t offset;
};

struct ExprError {
  std::size_t offset = 0;
  std::string message;
};

// Splits text into tokens ending with kEnd. Returns an error for any character outside the
// grammar, integers with more than 6 digits, and text longer than max_length. A name may hold
// placeholders "{name}" (kept in its text, braces included).
std::optional<ExprError> Lex(std::string_view text, std::vector<Token>& out,
                             std::size_t max_length = kMaxExprLength);

enum class IndexKind { kI, kIPlus1, kFixed };

struct Index {
  IndexKind kind = IndexKind::kI;
  int fixed = 0;  // for kFixed
  std::size_t offset = 0;
};

// What a variable name resolves to (filled in by Check).
enum class VarKind { kUnresolved, kLocation, kCommand, kEpisodeState, kTemporalState };

struct Expr {
  enum class Op { kTrue, kFalse, kAtom, kNot, kAnd, kOr, kImplies, kIff, kEvery, kAny };
  Op op = Op::kTrue;
  std::size_t offset = 0;
  std::vector<Expr> kids;  // kNot, kEvery, kAny: 1 (the body); binary connectives: 2

  // kAtom only.
  std::string var;
  std::size_t var_offset = 0;
  Index index;
  bool not_equal = false;
  std::string value;
  std::size_t value_offset = 0;

  // kEvery / kAny only: the bound variable (in `var`, at var_offset) and its range: a template's
  // name (`range`), or the integers range_lo..range_hi when `range` is empty; at range_offset.
  std::string range;
  int range_lo = 0, range_hi = -1;
  std::size_t range_offset = 0;

  // An atom made by expanding a quantifier: its variables' values ("k=3"), for messages.
  std::string binding;

  // Filled in by Check: the automaton / episode / temporal constraint index, and the value's
  // code (location index, command index with 0 = no-op, or accepting-automaton state).
  VarKind var_kind = VarKind::kUnresolved;
  int target = -1;
  int value_code = -1;
};

// Parses text into a tree. Returns nullopt and sets err on failure. A placeholder "{k}" outside
// a quantifier binding k is an error.
std::optional<Expr> Parse(std::string_view text, ExprError& err,
                          std::size_t max_length = kMaxExprLength);

// True when e holds a quantifier (kEvery or kAny) anywhere.
bool HasQuantifier(const Expr& e);

// Human-readable name of a token kind for "expected ..." messages.
const char* TokName(TokKind kind);

}  // namespace ctb
