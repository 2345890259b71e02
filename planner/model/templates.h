// Automaton templates: a pure JSON -> JSON expansion that runs before LoadDomain (contract
// section 12, docs/domains.md). The rest of the planner only ever sees plain automata.
//
// A domain document may declare
//   "parameters": {"N": 2}                       integer constants (overridable)
// and, in "automata", beside plain automata, templates:
//   {"template": "robot", "parameter": "k", "instances": "1..N",
//    "locations": [...], "commands": [...], "transitions": [...]}
// expanded, in place, to one automaton per instance value, named template + value (robot1 ..
// robotN). Inside a template or a plain automaton:
//   - "{expr}" in any name or guard is replaced by the value of expr: a parameter, the template's
//     parameter, a loop variable, `self` (the instance's name), or integer arithmetic (+ - * and
//     parentheses) over them;
//   - an item {"for": "p", "in": RANGE, "each": ITEM or [ITEMS]} of "locations", "commands" or
//     "transitions" stands for its items once per value of p;
//   - a guard may say any(k in RANGE: BODY) / every(k in RANGE: BODY): the disjunction /
//     conjunction of BODY over the values (an empty range gives false / true).
// RANGE is "A..B" (integer expressions), the name of a template (its instance values), or a JSON
// array of integers or name fragments.
//
// Errors point into the document as written (the template's own pointer), and name the instance
// ("in instance 'robot3' (k=3)"). Never throws.
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "planner/model/error.h"
#include "planner/model/json_io.h"

namespace ctb {

// The longest guard any(...)/every(...) may expand to (a guard as written has at most
// kMaxExprLength characters; "any robot opens the door" over 1,000 robots needs about 30,000), and
// the characters all the guards of one document may expand to: the expansion's work is bounded
// by these, whatever the nesting of its quantifiers.
constexpr std::size_t kMaxExpandedGuard = 1 << 16;
constexpr std::size_t kMaxExpandedGuards = 1 << 24;

// Where a part of the expanded document came from.
struct SourceMapEntry {
  std::string expanded;  // pointer into the expanded document (an automaton, an item)
  std::string source;    // pointer into the document as written
  std::string instance;  // "instance 'robot3' (k=3)", "p=2", or "" for a plain part
};

// A template of a document: its instances are the automata named name + value, for each value
// ("1", "2", ... or a name fragment), in order.
struct TemplateRange {
  std::string name;
  std::vector<std::string> values;
};

struct Expansion {
  Json document;                       // the expanded document, plain automata only
  std::vector<SourceMapEntry> source;  // longest matching prefix wins
  bool had_templates = false;          // the document used any template feature
  std::vector<TemplateRange> templates;  // every template declared, in the document's order
};

struct ExpandOptions {
  std::map<std::string, long> parameters;  // overrides of "parameters" (each must be declared)
};

// True when the document uses "parameters", a template, a "for" item, or a placeholder.
bool UsesTemplates(const Json& doc);

// True when the document has no "parameters" and its automata no "for" or "template" item and no
// brace in any string: it expands to itself (checked without expanding it; the expander's copy of
// a large plain domain took half a second).
bool ObviouslyPlain(const Json& doc);

// Expands doc. On error returns nullopt with every problem in diags, at the document's pointers.
std::optional<Expansion> ExpandTemplates(const Json& doc, Diagnostics& diags,
                                         const ExpandOptions& options = {});

// Rewrites diagnostics about the expanded document into ones about the document as written:
// the pointer mapped back, the instance named, and an offset inside a guard that the expansion
// changed given as text (the offset refers to the expanded guard, which the message quotes).
void MapDiagnostics(const Expansion& x, const Json& original, const Diagnostics& expanded_diags,
                    Diagnostics& out);

}  // namespace ctb
