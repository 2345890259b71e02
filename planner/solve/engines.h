// The exact engines and the names `search` gives them (SolveOptions::search, the CLI's
// --search, bench/): one table instead of string comparisons spread over the solve library.
// Internal to planner/solve.
#pragma once

#include <string>
#include <vector>

#include "planner/solve/backend.h"

namespace ctb::solve {

// One way to run a model: a Gecode search strategy (encode_objective.cpp) or the z3 engine.
struct Engine {
  const char* search;    // the name `search` uses
  bool z3;               // the z3 engine (its own model); else Gecode through MiniZinc
  bool in_portfolio;     // a member of "portfolio", in table order
};

// Every engine, in table order: g_first, tc_first, z3 (the portfolio's members), first_fail,
// transitions_first, default.
const std::vector<Engine>& Engines();

// The engine `search` names, or nullptr ("portfolio" and unknown names).
const Engine* FindEngine(const std::string& search);

// Every accepted value of `search`: "portfolio" and each engine's name, comma-separated.
std::string SearchNames();

// The engine's backend: z3's own, else the given Gecode backend.
SolverBackend& BackendOf(const Engine& e, SolverBackend& gecode);

// The strategy the MiniZinc model is written with (z3 reads the g_first model's structure).
inline const char* ModelStrategy(const Engine& e) { return e.z3 ? "g_first" : e.search; }

}  // namespace ctb::solve
