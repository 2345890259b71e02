#include "planner/solve/engines.h"

namespace ctb::solve {

const std::vector<Engine>& Engines() {
  static const std::vector<Engine> kAll = {
      {"g_first", false, true},           {"tc_first", false, true}, {"z3", true, true},
      {"first_fail", false, false},       {"transitions_first", false, false},
      {"default", false, false},
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

SolverBackend& BackendOf(const Engine& e, SolverBackend& gecode) {
  return e.z3 ? Z3EngineBackend() : gecode;
}

}  // namespace ctb::solve
