// Import of PDDL 2.1 temporal domains into ctburton action models (docs/domains.md, "Importing
// PDDL"; contract section 2 for the output).
//
// A domain whose fluents group into mutually exclusive state variables (per object, the
// predicates that an action deletes one of and adds another of) becomes one automaton per state
// variable, its values the locations. A durative action that moves one variable from a to b
// becomes a commanded transition a -> "<action>_<args>" (a timed location) and an automatic one
// to b after the action's duration; its other at-start and over-all conditions become guards.
// What cannot be mapped (an action changing two variables, numeric fluents, disjunctive or
// at-end conditions, ...) is an Issue naming the action and the line, never a silent drop.
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
};

struct Imported {
  Json domain;      // an action model (contract section 2) that LoadDomain accepts
  Json state_plan;  // with a problem: initial state, goal, objective; else null
  std::vector<Issue> warnings;
  std::size_t ground_actions = 0;
};

// Reads a domain (and, when given, a problem whose objects and :init ground it; without one the
// domain's constants are the objects) and writes the action model. On failure every issue found
// (reading stops at the first stage with issues: syntax, analysis, grounding, writing).
std::variant<Imported, std::vector<Issue>> ImportPddl(const Source& domain,
                                                      const std::optional<Source>& problem,
                                                      const ImportOptions& options = {});

}  // namespace ctb::pddl
