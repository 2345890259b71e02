#include "planner/solve/plan_check.h"

namespace ctb {

const char* PlanCheckName(PlanCheck c) {
  switch (c) {
    case PlanCheck::kValid: return "valid";
    case PlanCheck::kInvalid: return "invalid";
    case PlanCheck::kUnknown: return "unknown";
  }
  return "unknown";
}

std::shared_ptr<History> HistoryOfRun(const Trajectory& t, std::size_t automata) {
  auto h = std::make_shared<History>();
  const int g = t.goal_event;
  h->times.assign(t.events.begin(), t.events.begin() + g + 1);
  h->locations.assign(automata, {});
  h->entry.assign(automata, std::vector<long>(g + 1, 0));
  for (std::size_t a = 0; a < automata; ++a)
    h->locations[a].assign(t.locations[a].begin(), t.locations[a].begin() + g + 1);
  for (const auto& f : t.fired)
    if (f.event <= g) h->fired.push_back(f);
  // An automaton entered its location at its last transition up to each stage (fired is in event
  // order): mark the transitions' events, then carry the times forward.
  for (const auto& f : h->fired) h->entry[f.automaton][f.event] = t.events[f.event];
  for (std::size_t a = 0; a < automata; ++a)
    for (int k = 1; k <= g; ++k)
      if (h->entry[a][k] == 0) h->entry[a][k] = h->entry[a][k - 1];
  h->now = t.events[g];
  return h;
}

PlanCheck CheckPlanAgainst(const Trajectory& t, const Domain& d, const StatePlan& sp,
                           const SolveOptions& base) {
  if (t.goal_event < 0 || static_cast<int>(t.events.size()) <= t.goal_event ||
      t.locations.size() != d.automata.size())
    return PlanCheck::kInvalid;
  for (std::size_t a = 0; a < d.automata.size(); ++a)
    if (t.locations[a].empty() || t.locations[a][0] != sp.initial[a]) return PlanCheck::kInvalid;
  // The run is fixed as a history, where forbidden actions are not checked (they may have
  // happened before a replan): check them here.
  for (int j : sp.forbidden)
    for (const auto& f : t.fired)
      if (sp.actions[j].Names(f.automaton, f.transition)) return PlanCheck::kInvalid;
  SolveOptions o = base;
  o.history = HistoryOfRun(t, d.automata.size());
  o.horizon = t.goal_event;
  o.first_horizon = 0;
  o.objective = Objective::kCost;
  o.first_plan_ms = 0;
  o.derive_network = false;
  o.plan_out = nullptr;
  o.on_progress = nullptr;
  o.model_out.clear();
  auto r = Solve(d, sp, o);
  const SolveResult* res = std::get_if<SolveResult>(&r);
  if (!res) return PlanCheck::kUnknown;
  switch (res->status) {
    case Termination::kOptimal:
    case Termination::kFeasible: return res->verified() ? PlanCheck::kValid : PlanCheck::kUnknown;
    case Termination::kInfeasible: return PlanCheck::kInvalid;
    case Termination::kUnknown: return PlanCheck::kUnknown;
  }
  return PlanCheck::kUnknown;
}

}  // namespace ctb
