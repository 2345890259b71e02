#include "planner/solve/engines.h"

namespace ctb::solve {

namespace {

SolverBackend& Gecode(SolverBackend& gecode) { return gecode; }
SolverBackend& Z3(SolverBackend&) { return Z3EngineBackend(); }

// A Gecode strategy: the solve's MiniZinc backend, its own search annotation, every problem.
constexpr Engine GecodeEngine(const char* search, bool in_portfolio) {
  return {search, &Gecode, search, true, true, true, in_portfolio};
}

}  // namespace

const std::vector<Engine>& Engines() {
  // z3 reads the g_first model's structure (the spec), has no history and no action rules.
  static const std::vector<Engine> kAll = {
      GecodeEngine("g_first", true),
      GecodeEngine("tc_first", true),
      {"z3", &Z3, "g_first", false, false, false, true},
      GecodeEngine("first_fail", false),
      GecodeEngine("transitions_first", false),
      GecodeEngine("default", false),
  };
  return kAll;
}

const Engine* FindEngine(const std::string& search) {
  for (const auto& e : Engines())
    if (search == e.search) return &e;
  return nullptr;
}

std::string SearchNames() {
  std::string out = "portfolio";
  for (const auto& e : Engines()) out += std::string(", ") + e.search;
  return out;
}

}  // namespace ctb::solve
