// The grouping analysis (internal to ctb_pddl): which fluents form mutually exclusive state
// variables (multi-valued groups), which are plain true/false atoms, and which change only by
// timed initial literals; decided on the lifted actions (and the problem's :init).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "interchange/pddl/internal/pddl_ast.h"

namespace ctb::pddl {

// A group of predicates that actions move between. A multi-valued group has, per owner (the
// arguments at each predicate's owner positions), exactly one atom true at a time: every action
// that deletes one adds another of the same owner and requires the one it deletes. Any other
// changed predicate is *boolean*: each ground atom is a variable of its own, true or false. A
// *timed* group is a boolean predicate that only timed initial literals change.
struct Group {
  std::vector<std::string> preds;                // in declaration order
  std::map<std::string, std::vector<int>> owner;  // per predicate: the owner's argument positions
  bool boolean = false;
  bool timed = false;
  std::string name;  // the first predicate's
};

struct StateVars {
  std::vector<Group> groups;
  std::map<std::string, int> group_of;  // fluent predicate -> group

  bool IsFluent(const std::string& pred) const { return group_of.count(pred) > 0; }
};

// Never fails on the domain's own account: a predicate that cannot be one value of a group is a
// boolean. Returns nullopt (issues appended, each located) when a timed initial literal changes a
// predicate that actions change too.
std::optional<StateVars> AnalyzeStateVars(const DomainAst& d, const ProblemAst* p,
                                          std::vector<Issue>& issues,
                                          std::vector<Issue>& warnings);

}  // namespace ctb::pddl
