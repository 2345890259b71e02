// The action model (a domain): parameterized concurrent timed automata (contract section 2).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "planner/model/error.h"
#include "planner/expr/expr.h"
#include "planner/expr/expr_info.h"
#include "planner/model/json_io.h"
#include "planner/model/templates.h"

namespace ctb {

struct Duration {
  double lo = 0;
  std::optional<double> hi;  // nullopt: unbounded
};

// How nature picks a contingent transition's duration within its bounds (contract section 13):
// uniform, or a normal distribution truncated to [lo, hi].
struct Distribution {
  enum class Kind { kUniform, kNormal };
  Kind kind = Kind::kUniform;
  double mean = 0, sd = 0;  // kNormal only
};

struct Transition {
  int from = -1;  // location indices within the automaton
  int to = -1;
  std::string guard_text = "true";
  Expr guard;               // checked: every atom resolved
  ExprInfo guard_info;      // what the guard reads
  Duration duration;
  long cost = 1;
  bool controllable = false;
  // Nature, not the planner, picks when it fires, anywhere in `duration` (hi finite; guard true;
  // the only transition out of its `from` location). Planned for at hi, checked for
  // controllability over [lo, hi] (contract section 13).
  bool contingent = false;
  std::optional<Distribution> distribution;  // contingent only
  bool commanded = false;   // derived: the guard reads the automaton's own command
  int command = 0;          // derived: the command code the guard requires (0: none or several)
  std::string pointer;      // JSON pointer of the transition, for messages
};

struct Automaton {
  std::string name;
  std::vector<std::string> locations;
  std::vector<std::string> commands;  // code 0 is the implicit no-op; commands[c] has code c+1
  std::vector<Transition> transitions;

  int LocationIndex(const std::string& n) const;  // -1 when absent
  int CommandCode(const std::string& n) const;    // 1-based; -1 when absent
};

struct Domain {
  std::string name;
  std::string description;
  double time_resolution = 1.0;  // seconds per solver time unit
  std::vector<Automaton> automata;
  // The templates the document declared (empty for a plain domain): the ranges of the
  // expression language's quantifiers (every(k in robot: ...), expr.h).
  std::vector<TemplateRange> templates;

  int AutomatonIndex(const std::string& n) const;  // -1 when absent
  const TemplateRange* Template(const std::string& n) const;  // nullptr when absent
  bool HasContingent() const;
};

// The domain the exact and heuristic engines plan with: every contingent transition takes its
// longest duration ([hi, hi], automatic), the worst case of contract section 13; with
// `planner_picks` (options.controllability "none") it is controllable in [lo, hi] instead.
Domain PlanningDomain(const Domain& d, bool planner_picks);

// Loads and checks a domain. Templates (templates.h) are expanded first, with the parameters'
// declared values; errors in a template point at the template and name the instance. On any
// error returns nullopt with every problem in diags, each at the JSON pointer of the offending
// value (and the offset inside a guard string). Never throws.
// The command code a guard requires of automaton `automaton`: a positive atom "<name>u[i]==c" in
// its top-level conjunction. 0 when it requires none that way, -1 when two different ones.
int RequiredCommand(const Expr& guard, int automaton);

std::optional<Domain> LoadDomain(const Json& j, Diagnostics& diags);
// The same with template parameters overridden; *expansion (when given) receives the expanded
// document, also when the domain does not load (unless the expansion itself failed).
std::optional<Domain> LoadDomain(const Json& j, Diagnostics& diags, const ExpandOptions& options,
                                 Expansion* expansion = nullptr);
std::optional<Domain> LoadDomainFile(const std::string& path, Diagnostics& diags,
                                     const ParseLimits& limits = {});

// Serializes a loaded domain back to the contract's JSON (for GET /domains/{name}).
Json DomainToJson(const Domain& d);

// True when s is a name usable in expressions: [A-Za-z_][A-Za-z0-9_]*, not a keyword.
bool IsIdentifier(const std::string& s);

}  // namespace ctb
