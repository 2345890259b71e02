// Grounding (internal to ctb_pddl): the lifted actions over the objects, each a change of one
// ground state variable with its conditions on others and its duration; the variables with
// their values and, with a problem, their initial values.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "interchange/pddl/internal/state_vars.h"

namespace ctb::pddl {

// A ground state variable: its group and its owner objects (the first argument of the group's
// atoms, none for 0-ary ones; every argument of a boolean group's atom).
struct VarKey {
  int group = -1;
  std::vector<std::string> owner;
  auto operator<=>(const VarKey&) const = default;
};

// A value: "pred arg..." (the arguments after the owner) for a move group; for a boolean group
// "pred" (the atom holds) or "not pred".
std::string NotValue(const std::string& pred);

struct GroundLit {
  VarKey var;
  std::string value;
  bool positive = true;
  bool over_all = false;
  std::string text;  // the lifted literal, for messages
};

struct GroundAction {
  int action = -1;  // index into DomainAst::actions
  std::vector<std::string> args;
  VarKey var;
  std::string from, to;
  std::vector<GroundLit> conditions;  // on other variables, at start or over all
  double lo = 0;
  std::optional<double> hi;  // nullopt: unbounded
};

struct Variable {
  VarKey key;
  std::vector<std::string> values;  // the initial value (when known) first
  std::optional<std::string> initial;
};

struct Grounded {
  std::vector<std::string> objects;  // declaration order: constants, then the problem's
  std::set<std::string> facts;       // GroundKey of every :init atom
  std::vector<Variable> variables;   // by group, then owner in object order
  std::vector<GroundAction> actions;
  bool has_problem = false;

  // The variable and value a ground fluent atom reads; nullopt for a static predicate.
  std::optional<std::pair<VarKey, std::string>> Locate(const StateVars& sv, const Atom& a) const;
};

// On error nullopt with every issue appended; what is left out (an object without an initial
// value, actions whose durations are undefined) is reported in `warnings`.
std::optional<Grounded> Ground(const DomainAst& d, const StateVars& sv, const ProblemAst* p,
                               const ImportOptions& options, std::vector<Issue>& issues,
                               std::vector<Issue>& warnings);

}  // namespace ctb::pddl
