#include "app/solution_event.h"

#include <cmath>

namespace ctb::app {

namespace {

// 2430.0 -> 2430; 12.5 stays.
Json Seconds(double s) {
  if (std::floor(s) == s && std::fabs(s) < 1e15) return static_cast<long long>(s);
  return s;
}

}  // namespace

Json SolutionEventJson(const SolveProgress& p) {
  const Json makespan = Seconds(p.value.MakespanSeconds());
  Json objective = p.value.cost;
  if (p.value.kind == Objective::kMakespan) objective = makespan;
  if (p.value.kind == Objective::kCostThenMakespan) objective = {{"cost", p.value.cost}, {"makespan", makespan}};
  return {{"kind", ObjectiveName(p.value.kind)}, {"cost", p.value.cost}, {"horizon", p.horizon},
          {"makespan", makespan}, {"elapsed_ms", p.elapsed_ms}, {"bound", p.bound.ToJson()},
          {"found_by", p.found_by.Name()}, {"objective", objective}, {"solve_ms", p.elapsed_ms}};
}

}  // namespace ctb::app
