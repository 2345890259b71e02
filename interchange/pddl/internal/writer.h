// The writer (internal to ctb_pddl): ground state variables and actions as automata (contract
// section 2), and a problem's initial state and goal as a state plan (section 3).
#pragma once

#include <optional>

#include "interchange/pddl/internal/grounding.h"

namespace ctb::pddl {

struct Written {
  Json domain;
  Json state_plan;              // null without a problem
  std::vector<Issue> warnings;  // what was approximated (durations rounded)
  std::vector<PlanAction> actions;
};

// On error (a goal on an unknown object, nothing to import) nullopt with the issue appended.
std::optional<Written> WriteModel(const DomainAst& d, const StateVars& sv, const Grounded& g,
                                  const ProblemAst* p, const ImportOptions& options,
                                  std::vector<Issue>& issues);

// A PDDL name as an identifier of the expression language: lower case, every character but
// letters, digits and '_' replaced by '_', a leading digit prefixed with '_', keywords suffixed.
std::string Identifier(const std::string& name);

}  // namespace ctb::pddl
