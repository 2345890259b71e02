// Grounding (internal to ctb_pddl): the actions over the objects, only the bindings whose
// conditions can become true (a relaxed reachability fixpoint from :init), each as what it
// requires of and does to each ground state variable; the variables with their values and, with
// a problem, their initial values and timed initial literals.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "interchange/pddl/internal/state_vars.h"

namespace ctb::pddl {

// A ground state variable: its group and its owner objects (the arguments at the owner
// positions; every argument of a boolean group's atom).
struct VarKey {
  int group = -1;
  std::vector<std::string> owner;
  auto operator<=>(const VarKey&) const = default;
};

// A value: "pred arg..." (the arguments outside the owner) for a multi-valued group; for a
// boolean group "pred" (the atom holds) or "not pred". kNoValue: a multi-valued variable between
// an at-start delete and an at-end add (none of its atoms holds).
std::string NotValue(const std::string& pred);
inline const std::string kNoValue = "-";

// What one ground action requires of one variable (by When: at start, over all, at end) and the
// value it gives it at start and at end.
struct VarUse {
  VarKey var;
  std::optional<std::string> need[3];
  std::vector<std::string> forbid[3];
  std::optional<std::string> eff_start, eff_end;
  bool Changes() const { return eff_start || eff_end; }
};

struct GroundAction {
  int action = -1;  // index into DomainAst::actions
  std::vector<std::string> args;
  std::vector<VarUse> uses;
  double lo = 0;
  std::optional<double> hi;  // nullopt: unbounded
};

struct Variable {
  VarKey key;
  std::vector<std::string> values;  // the initial value (when known) first
  std::optional<std::string> initial;
  std::vector<std::pair<double, std::string>> timeline;  // timed initial literals, by time
};

struct Grounded {
  std::vector<std::string> objects;  // declaration order: constants, then the problem's
  std::set<std::string> facts;       // GroundKey of every :init atom
  std::set<std::string> timed;       // GroundKey of every atom a timed initial literal changes
  std::vector<Variable> variables;   // by group, then owner in object order
  std::vector<GroundAction> actions;
  bool has_problem = false;

  // The variable and value a ground fluent atom reads; nullopt for a static atom.
  std::optional<std::pair<VarKey, std::string>> Locate(const StateVars& sv, const Atom& a) const;
};

// On error nullopt with every issue appended; what is left out (an object without an initial
// value, actions whose durations are undefined) is reported in `warnings`.
std::optional<Grounded> Ground(const DomainAst& d, const StateVars& sv, const ProblemAst* p,
                               const ImportOptions& options, std::vector<Issue>& issues,
                               std::vector<Issue>& warnings);

// Leaves out the ground actions that cannot help reach the goal: backwards from it, an action is
// relevant when it gives a variable a value that the goal or a relevant action's condition needs
// (or any value of a variable whose value is refused by a negative condition, or read by the goal
// under a disjunction or a negation). Every plan keeps being a plan without the others (their
// effects are never needed), and each plan of the rest is one of the whole. Returns how many were
// left out.
std::size_t DropIrrelevant(const StateVars& sv, const Goal& goal, Grounded& g);

}  // namespace ctb::pddl
