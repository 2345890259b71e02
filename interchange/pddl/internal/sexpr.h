// A small reader of s-expressions as PDDL writes them (internal to ctb_pddl).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "interchange/pddl/import.h"

namespace ctb::pddl {

struct Pos {
  int line = 0;    // 1-based
  int column = 0;  // 1-based
};

// An atom (a symbol or a number, lower-cased: PDDL is case-insensitive) or a list.
struct SExpr {
  bool is_list = false;
  std::string atom;
  std::vector<SExpr> items;
  Pos pos;

  bool IsAtom() const { return !is_list; }
  bool IsAtom(std::string_view s) const { return !is_list && atom == s; }
  // A list whose first item is the atom `head`.
  bool HasHead(std::string_view head) const;
  // The first item's atom; "" when this is an atom, an empty list or starts with a list.
  std::string Head() const;
  // The expression printed back on one line (at most max_chars, then "..."), for messages.
  std::string ToString(std::size_t max_chars = 80) const;
};

inline constexpr int kMaxSExprDepth = 64;
inline constexpr std::size_t kMaxPddlBytes = 4 << 20;

// Reads exactly one s-expression from text (comments run from ';' to the end of the line).
// On error returns nullopt and appends an Issue with the line and column.
std::optional<SExpr> ReadSExpr(std::string_view text, const std::string& file,
                               std::vector<Issue>& issues);

}  // namespace ctb::pddl
