// Import of PDDL 2.1 temporal domains into ctburton action models (docs/pddl.md; contract section
// 2 for the output).
//
// Fluents group into state variables (per owner, the predicates that actions move between; every
// other changed atom a true/false variable), one automaton each. A ground durative action is a
// command that every automaton it changes or reads takes at its start: the automata it changes at
// its start move then, those it changes at its end enter a step location and leave it together
// its duration later; over-all conditions are guards at the start and protections on other
// actions' transitions; the goal also asks that no action still runs. What cannot be mapped
// (numeric fluents, disjunctive conditions, conditional effects, ...) is an Issue naming the
// action and the line, never a silent drop; what is approximated is a warning.
//
// Never throws. Thread-safe: calls share nothing.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "planner/model/json_io.h"

namespace ctb::pddl {

// One problem found in the PDDL input: where (file, 1-based line and column; 0 when the input as
// a whole is meant), which action (empty outside one), and what.
struct Issue {
  std::string file;
  int line = 0;
  int column = 0;
  std::string action;
  std::string message;

  // "FILE:LINE:COLUMN: action 'NAME': MESSAGE" (the parts that are known).
  std::string ToString() const;
};

// A PDDL text and the name it is reported under.
struct Source {
  std::string file;
  std::string text;
};

struct ImportOptions {
  std::string name;                        // the domain's name; "" = the PDDL domain's, sanitized
  std::size_t max_ground_actions = 20000;  // beyond this the import is refused
  // With a problem, ground actions that cannot help reach its goal are left out of the model
  // (DropIrrelevant, docs/pddl.md); true keeps them (a model to reuse with other goals).
  bool keep_irrelevant = false;
};

// A ground action as the model names it: its command, the automaton whose transitions on that
// command mark its start and end (its timing automaton), and the PDDL "(name arg...)".
struct PlanAction {
  std::string command;
  std::string automaton;
  std::string pddl;
  bool durative = true;
};

struct Imported {
  Json domain;      // an action model (contract section 2) that LoadDomain accepts
  Json state_plan;  // with a problem: initial state, goal, objective; else null
  std::vector<Issue> warnings;
  std::size_t ground_actions = 0;     // in the model
  std::size_t irrelevant_actions = 0;  // ground, but left out: they cannot help reach the goal
  std::vector<PlanAction> actions;  // those that appear in the model
};

// Reads a domain (and, when given, a problem whose objects and :init ground it; without one the
// domain's constants are the objects) and writes the action model. On failure every issue found
// (reading stops at the first stage with issues: syntax, analysis, grounding, writing).
std::variant<Imported, std::vector<Issue>> ImportPddl(const Source& domain,
                                                      const std::optional<Source>& problem,
                                                      const ImportOptions& options = {});

// A trajectory (contract section 5) of a model imported as `actions` says as a PDDL 2.1 plan, one
// line per action in start order: "TIME: (name arg...) [DURATION]" (no duration for an
// instantaneous action), times in seconds with 3 decimals. Events that share a time keep their
// order in the file (no epsilon is added between them). An action started but not ended in the
// trajectory is left out (never in a plan that reached its goal). Never throws.
std::string PddlPlan(const Json& trajectory, const std::vector<PlanAction>& actions);

}  // namespace ctb::pddl
