#include <cctype>

#include "planner/expr/expr.h"

namespace ctb {

const char* TokName(TokKind kind) {
  switch (kind) {
    case TokKind::kIdent: return "a name";
    case TokKind::kInt: return "an integer";
    case TokKind::kLBracket: return "'['";
    case TokKind::kRBracket: return "']'";
    case TokKind::kLParen: return "'('";
    case TokKind::kRParen: return "')'";
    case TokKind::kPlus: return "'+'";
    case TokKind::kEq: return "'=='";
    case TokKind::kNe: return "'!='";
    case TokKind::kAnd: return "'/\\'";
    case TokKind::kOr: return "'\\/'";
    case TokKind::kImplies: return "'->'";
    case TokKind::kIff: return "'<->'";
    case TokKind::kNot: return "'not'";
    case TokKind::kTrue: return "'true'";
    case TokKind::kFalse: return "'false'";
    case TokKind::kColon: return "':'";
    case TokKind::kDotDot: return "'..'";
    case TokKind::kEnd: return "the end of the expression";
  }
  return "a token";
}

std::optional<ExprError> Lex(std::string_view text, std::vector<Token>& out,
                             std::size_t max_length) {
  out.clear();
  if (text.size() > max_length)
    return ExprError{max_length, "expression longer than " + std::to_string(max_length) +
                                     " characters"};
  std::size_t i = 0;
  const std::size_t n = text.size();
  auto starts = [&](std::string_view s) { return text.substr(i, s.size()) == s; };
  while (i < n) {
    unsigned char c = static_cast<unsigned char>(text[i]);
    if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
      ++i;
      continue;
    }
    std::size_t start = i;
    if (std::isalpha(c) || c == '_' || c == '{') {
      // A name, with placeholders "{k}" anywhere in it (Parse checks that a quantifier binds k).
      while (i < n) {
        const unsigned char d = static_cast<unsigned char>(text[i]);
        if (std::isalnum(d) || d == '_') {
          ++i;
          continue;
        }
        if (d != '{') break;
        std::size_t close = i + 1;
        while (close < n && (std::isalnum(static_cast<unsigned char>(text[close])) ||
                             text[close] == '_'))
          ++close;
        if (close == i + 1 || std::isdigit(static_cast<unsigned char>(text[i + 1])) ||
            close >= n || text[close] != '}')
          return ExprError{i, "a placeholder is '{' a quantifier's variable '}', e.g. 'robot{k}l'"};
        i = close + 1;
      }
      std::string word(text.substr(start, i - start));
      TokKind kind = TokKind::kIdent;
      if (word == "not") kind = TokKind::kNot;
      else if (word == "true") kind = TokKind::kTrue;
      else if (word == "false") kind = TokKind::kFalse;
      out.push_back({kind, std::move(word), start});
      continue;
    }
    if (std::isdigit(c)) {
      while (i < n && std::isdigit(static_cast<unsigned char>(text[i]))) ++i;
      if (i - start > 6) return ExprError{start, "integer too large"};
      if (i < n && (std::isalpha(static_cast<unsigned char>(text[i])) || text[i] == '_'))
        return ExprError{i, "unexpected character '" + std::string(1, text[i]) +
                                "' after a number"};
      out.push_back({TokKind::kInt, std::string(text.substr(start, i - start)), start});
      continue;
    }
    TokKind kind;
    std::size_t len = 1;
    if (starts("<->")) kind = TokKind::kIff, len = 3;
    else if (starts("->")) kind = TokKind::kImplies, len = 2;
    else if (starts("/\\")) kind = TokKind::kAnd, len = 2;
    else if (starts("\\/")) kind = TokKind::kOr, len = 2;
    else if (starts("==")) kind = TokKind::kEq, len = 2;
    else if (starts("!=")) kind = TokKind::kNe, len = 2;
    else if (c == '=') kind = TokKind::kEq;
    else if (c == '[') kind = TokKind::kLBracket;
    else if (c == ']') kind = TokKind::kRBracket;
    else if (c == '(') kind = TokKind::kLParen;
    else if (c == ')') kind = TokKind::kRParen;
    else if (c == '+') kind = TokKind::kPlus;
    else if (c == ':') kind = TokKind::kColon;
    else if (starts("..")) kind = TokKind::kDotDot, len = 2;
    else {
      std::string shown = (c >= 0x20 && c < 0x7f) ? "'" + std::string(1, static_cast<char>(c)) + "'"
                                                   : "byte " + std::to_string(c);
      return ExprError{start, "unexpected character " + shown};
    }
    out.push_back({kind, std::string(text.substr(start, len)), start});
    i += len;
  }
  out.push_back({TokKind::kEnd, "", n});
  return std::nullopt;
}

}  // namespace ctb
