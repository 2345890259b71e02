#include "interchange/pddl/internal/sexpr.h"

#include <cctype>

namespace ctb::pddl {

bool SExpr::HasHead(std::string_view head) const {
  return is_list && !items.empty() && items[0].IsAtom(head);
}

std::string SExpr::Head() const {
  return is_list && !items.empty() && items[0].IsAtom() ? items[0].atom : std::string();
}

namespace {

void Print(const SExpr& e, std::string& out, std::size_t max_chars) {
  if (out.size() > max_chars) return;
  if (!e.is_list) {
    out += e.atom;
    return;
  }
  out += '(';
  for (std::size_t i = 0; i < e.items.size(); ++i) {
    if (i) out += ' ';
    Print(e.items[i], out, max_chars);
  }
  out += ')';
}

bool IsDelimiter(char c) {
  return std::isspace(static_cast<unsigned char>(c)) || c == '(' || c == ')' || c == ';';
}

Issue At(const std::string& file, Pos p, std::string message) {
  return Issue{file, p.line, p.column, "", std::move(message)};
}

}  // namespace

std::string SExpr::ToString(std::size_t max_chars) const {
  std::string out;
  Print(*this, out, max_chars);
  if (out.size() > max_chars) out = out.substr(0, max_chars) + "...";
  return out;
}

std::optional<SExpr> ReadSExpr(std::string_view text, const std::string& file,
                               std::vector<Issue>& issues) {
  if (text.size() > kMaxPddlBytes) {
    issues.push_back(At(file, {}, "file larger than " + std::to_string(kMaxPddlBytes) + " bytes"));
    return std::nullopt;
  }
  // An explicit stack of open lists: no recursion on untrusted nesting.
  std::vector<SExpr> open;
  std::optional<SExpr> done;
  Pos pos{1, 1};
  std::size_t i = 0;
  auto advance = [&](std::size_t n) {
    for (std::size_t k = 0; k < n; ++k, ++i) {
      if (text[i] == '\n') {
        ++pos.line;
        pos.column = 1;
      } else {
        ++pos.column;
      }
    }
  };
  auto emit = [&](SExpr e) -> bool {
    if (!open.empty()) {
      open.back().items.push_back(std::move(e));
      return true;
    }
    if (done) {
      issues.push_back(At(file, e.pos, "text after the end of the PDDL definition"));
      return false;
    }
    done = std::move(e);
    return true;
  };
  while (i < text.size()) {
    char c = text[i];
    if (std::isspace(static_cast<unsigned char>(c))) {
      advance(1);
    } else if (c == ';') {
      while (i < text.size() && text[i] != '\n') advance(1);
    } else if (c == '(') {
      if (static_cast<int>(open.size()) >= kMaxSExprDepth) {
        issues.push_back(
            At(file, pos, "nested more than " + std::to_string(kMaxSExprDepth) + " levels deep"));
        return std::nullopt;
      }
      SExpr e;
      e.is_list = true;
      e.pos = pos;
      open.push_back(std::move(e));
      advance(1);
    } else if (c == ')') {
      if (open.empty()) {
        issues.push_back(At(file, pos, "')' without a matching '('"));
        return std::nullopt;
      }
      SExpr e = std::move(open.back());
      open.pop_back();
      advance(1);
      if (!emit(std::move(e))) return std::nullopt;
    } else {
      SExpr e;
      e.pos = pos;
      std::size_t start = i;
      // "-goods" in a typed list is "- goods" (IPC 2006 TPP writes it so): a '-' before a letter
      // is a token of its own, since no PDDL name starts with '-'.
      bool dash = text[i] == '-' && i + 1 < text.size() &&
                  std::isalpha(static_cast<unsigned char>(text[i + 1]));
      if (dash) {
        advance(1);
      } else {
        while (i < text.size() && !IsDelimiter(text[i])) advance(1);
      }
      for (std::size_t k = start; k < i; ++k)
        e.atom += static_cast<char>(std::tolower(static_cast<unsigned char>(text[k])));
      if (!emit(std::move(e))) return std::nullopt;
    }
  }
  if (!open.empty()) {
    issues.push_back(At(file, open.back().pos, "'(' is never closed"));
    return std::nullopt;
  }
  if (!done) {
    issues.push_back(At(file, pos, "no PDDL definition (the file is empty)"));
    return std::nullopt;
  }
  return done;
}

}  // namespace ctb::pddl
