// The exact engines and the names `search` gives them (SolveOptions::search, the CLI's
// --search, bench/): one table instead of string comparisons spread over the solve library.
// Internal to planner/solve.
#pragma once

#include <string>
#include <vector>

#include "planner/solve/backend.h"

namespace ctb::solve {

// One way to run a model: a Gecode search strategy (encode_objective.cpp) or the z3 engine. What
// an engine can take and how its backend is made are the table's, so that the solve library
// asks the engine instead of comparing names.
struct Engine {
  const char* search;  // the name `search` uses
  // Makes the engine's backend, given the solve's Gecode backend (SolveOptions::backend or
  // MiniZinc's): Gecode strategies run on it, z3 on its own.
  SolverBackend& (*backend)(SolverBackend& gecode);
  const char* model_strategy;  // the search annotation its MiniZinc model is written with
  bool reads_model_text;       // runs the MiniZinc text; else builds its own model from the spec
  bool takes_history;          // can start from a fixed history (replanning)
  bool takes_action_rules;     // can hold actions ordered or forbidden (contract section 15)
  bool in_portfolio;           // a member of "portfolio", in table order
};

// Every engine, in table order: g_first, tc_first, z3 (the portfolio's members), first_fail,
// transitions_first, default.
const std::vector<Engine>& Engines();

// The engine `search` names, or nullptr ("portfolio" and unknown names).
const Engine* FindEngine(const std::string& search);

// Every accepted value of `search`: "portfolio" and each engine's name, comma-separated.
std::string SearchNames();

// The engine's backend (Engine::backend).
inline SolverBackend& BackendOf(const Engine& e, SolverBackend& gecode) { return e.backend(gecode); }

// Whether the engine can take a problem with a history and/or action rules.
inline bool Takes(const Engine& e, bool history, bool action_rules) {
  return (!history || e.takes_history) && (!action_rules || e.takes_action_rules);
}

}  // namespace ctb::solve
