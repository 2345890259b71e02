// The grouping analysis (internal to ctb_pddl): which fluents form mutually exclusive state
// variables, and what each action does to its one variable, on the lifted actions.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "interchange/pddl/internal/pddl_ast.h"

namespace ctb::pddl {

// Predicates that actions move between: per owner object (the first argument) exactly one atom
// of the group holds. A *boolean* group is one predicate that actions add or delete alone: each
// of its ground atoms is a variable of its own, true or false.
struct Group {
  std::vector<std::string> preds;  // in declaration order
  bool boolean = false;
  std::string name;  // the first predicate's
};

// What one action does, lifted: leaves the value `del` for `add` (a move), or for a boolean
// group switches one atom (only `add` or only `del`; both when it re-adds what it deleted).
struct ActionChange {
  int group = -1;
  std::optional<Literal> del;
  std::optional<Literal> add;
};

struct StateVars {
  std::vector<Group> groups;
  std::map<std::string, int> group_of;               // fluent predicate -> group
  std::vector<std::optional<ActionChange>> changes;  // per action; nullopt: changes nothing

  bool IsFluent(const std::string& pred) const { return group_of.count(pred) > 0; }
};

// On error nullopt with every issue (each naming its action) appended to `issues`; warnings (an
// action that changes nothing is left out) go to `warnings`.
std::optional<StateVars> AnalyzeStateVars(const DomainAst& d, std::vector<Issue>& issues,
                                          std::vector<Issue>& warnings);

}  // namespace ctb::pddl
