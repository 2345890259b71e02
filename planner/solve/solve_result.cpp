#include "planner/solve/solve_result.h"

namespace ctb {

const char* TerminationName(Termination t) {
  switch (t) {
    case Termination::kOptimal: return "optimal";
    case Termination::kFeasible: return "feasible";
    case Termination::kInfeasible: return "infeasible";
    case Termination::kUnknown: return "unknown";
  }
  return "unknown";
}

const char* InfeasibleScopeName(InfeasibleScope s) {
  switch (s) {
    case InfeasibleScope::kNone: return "";
    case InfeasibleScope::kMaxHorizon: return "max_horizon";
    case InfeasibleScope::kAnyHorizon: return "any_horizon";
  }
  return "";
}

const char* ExplanationStatusName(ExplanationStatus s) {
  switch (s) {
    case ExplanationStatus::kMinimal: return "minimal";
    case ExplanationStatus::kUnknown: return "unknown";
    case ExplanationStatus::kControllability: return "controllability";
  }
  return "unknown";
}

Json ExplanationJson(const Explanation& e) {
  Json conflicts = Json::array(), relaxations = Json::array();
  for (const auto& c : e.conflicts) {
    Json j = {{"constraints", c.constraints}, {"text", c.text}};
    if (!c.broken_at.is_null()) j["broken_at"] = c.broken_at;
    conflicts.push_back(std::move(j));
  }
  for (const auto& r : e.relaxations) relaxations.push_back({{"changes", r.changes}, {"text", r.text}});
  Json out = {{"conflicts", conflicts}, {"relaxations", relaxations},
              {"status", ExplanationStatusName(e.status)}};
  if (e.consistent) out["consistent"] = *e.consistent;
  if (!e.stats.is_null()) out["stats"] = e.stats;
  if (!e.error.empty()) out["error"] = e.error;
  return out;
}

std::string Credit::Name() const {
  switch (method) {
    case Method::kNone: return "";
    case Method::kEngine: return engine;
    case Method::kHeuristic: return "heuristic";
    case Method::kLowerBound: return "lower bound";
    case Method::kStaticAnalysis: return "static analysis";
    case Method::kHistoryCheck: return "history check";
    case Method::kZoneSearch: return "zone search";
  }
  return "";
}

std::optional<ObjectiveValue> SolveResult::Value() const {
  if (!plan) return std::nullopt;
  return ObjectiveValue{objective, cost, makespan_ticks, ticks_per_second};
}

namespace {

Json StatsJson(const SolveResult& r) {
  const SolveStats& s = r.stats;
  Json out = {{"solver", s.solver},
              {"found_by", r.plan && !s.found_by.empty() ? Json(s.found_by.Name()) : Json()},
              {"proved_by", Proven(r.status) && !s.proved_by.empty() ? Json(s.proved_by.Name()) : Json()},
              {"compile_ms", s.compile_ms},
              {"solve_ms", s.solve_ms},
              {"first_solution_ms", s.first_solution_ms},
              {"variables", s.variables},
              {"solver_runs", s.solver_runs}};
  for (const auto& [k, v] : s.extra.items()) out[k] = v;
  return out;
}

}  // namespace

Json ObjectiveJson(const SolveResult& r) {
  const auto value = r.Value();
  return {{"kind", ObjectiveName(r.objective)}, {"value", value ? value->ToJson() : Json()}};
}

Json ResultJson(const SolveResult& r, const Domain& d, const StatePlan& sp) {
  Json out;
  out["status"] = TerminationName(r.status);
  out["objective"] = ObjectiveJson(r);
  if (r.plan) {
    out["cost"] = r.cost;
    Json trajectory = TrajectoryToJson(*r.plan, d, sp, r.ticks_per_second);
    for (auto& [k, v] : trajectory.items()) out[k] = std::move(v);
  } else {
    out["horizon"] = r.horizon;
  }
  out["max_horizon"] = r.max_horizon;
  if (r.bound) out["bound"] = r.bound->ToJson();
  out["verified"] = r.verified();
  if (r.scope != InfeasibleScope::kNone) out["infeasible_for"] = InfeasibleScopeName(r.scope);
  if (!r.message.empty()) out["message"] = r.message;
  out["stats"] = StatsJson(r);
  if (r.network) out["network"] = *r.network;
  if (r.slack) out["slack"] = *r.slack;
  if (r.controllability) out["controllability"] = *r.controllability;
  if (r.summary) out["state_plan_summary"] = *r.summary;
  if (r.explanation) out["explanation"] = ExplanationJson(*r.explanation);
  return out;
}

}  // namespace ctb
