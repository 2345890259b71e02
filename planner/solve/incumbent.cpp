#include "planner/solve/incumbent.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include <spdlog/spdlog.h>

#include "planner/search/first_plan.h"
#include "planner/search/neighbourhood.h"
#include "planner/verify/verify.h"

namespace ctb::solve {

long FirstPlanBudgetMs(const SolveOptions& o) {
  if (o.first_plan_ms >= 0) return o.first_plan_ms;
  return std::min(500L, o.time_limit_ms / 10);
}

namespace {

// Large-neighbourhood search (planner/search/neighbourhood.h) on the engine's plan that does not
// meet the bound, for a second budget as long as the first; `accept` verifies and keeps a plan.
// `plan` is a copy: `accept` replaces the plan it came from while the search runs.
void ImproveIncumbent(const Domain& d, const StatePlan& sp, const SolveOptions& o,
                      Objective objective, int max_events, const ObjectiveBounds& bounds,
                      long budget, const std::function<void(const Trajectory&, long, long)>& accept,
                      Plan plan, Json& stats) {
  NeighbourhoodOptions no;
  no.objective = objective;
  no.time_limit_ms = budget;
  no.max_events = max_events;
  no.cancel = o.cancel;
  no.good_enough = [&](long cost, long makespan) {
    return MeetsLowerBounds(bounds, objective, cost, makespan);
  };
  no.on_plan = accept;
  NeighbourhoodResult r = ImproveByNeighbourhoods(d, sp, plan.traj, plan.cost, plan.makespan, no);
  stats["neighbourhoods"] = {{"ms", r.elapsed_ms}, {"rounds", r.rounds}, {"improved", r.improved}};
}

}  // namespace

std::optional<Plan> FirstPlanIncumbent(const Domain& d, const StatePlan& sp, const SolveOptions& o,
                                       Objective objective, int max_events,
                                       const ObjectiveBounds& bounds, Clock::time_point t0,
                                       Json& stats, long& found_ms) {
  const long budget = FirstPlanBudgetMs(o);
  if (budget <= 0) return std::nullopt;
  const long tps = std::lround(1.0 / d.time_resolution);
  FirstPlanOptions fo;
  fo.objective = objective;
  fo.time_limit_ms = budget;
  fo.max_events = max_events;
  fo.cancel = o.cancel;
  fo.history = o.history;  // replanning: the plan is the whole run, the history included
  fo.good_enough = [&](long cost, long makespan) {
    return MeetsLowerBounds(bounds, objective, cost, makespan);
  };
  std::optional<Plan> best;
  fo.on_plan = [&](const Trajectory& t, long cost, long makespan) {
    // The same verifier as every engine's plan: one that fails is dropped, never shown.
    auto problems = VerifyTrajectory(t, d, sp, tps);
    if (!problems.empty()) {
      spdlog::error("first-plan engine: a plan failed verification ({}); dropped", problems[0]);
      return;
    }
    best = Plan{t, cost, makespan};
    found_ms = MsSince(t0);
    if (o.on_progress)
      o.on_progress({{objective, cost, makespan, tps}, BoundValue(bounds, objective, tps), t.goal_event,
                     found_ms, Credit{Method::kHeuristic, ""}});
  };
  FirstPlanResult r = FindFirstPlan(d, sp, fo);
  Json info = {{"ms", r.elapsed_ms}, {"expanded", r.expanded}, {"generated", r.generated},
               {"found", best.has_value()}};
  if (!r.declined.empty()) info["declined"] = r.declined;
  if (r.rejected > 0) {
    info["rejected"] = r.rejected;
    spdlog::error("first-plan engine: {} plan(s) failed verification", r.rejected);
  }
  stats["first_plan"] = info;
  if (best && !o.history && !MeetsLowerBounds(bounds, objective, best->cost, best->makespan))
    ImproveIncumbent(d, sp, o, objective, max_events, bounds,
                     std::min(budget, o.time_limit_ms - MsSince(t0)), fo.on_plan, *best, stats);
  return best;
}

}  // namespace ctb::solve
