#include "planner/solve/parts.h"

#include <cmath>
#include <map>

#include <spdlog/spdlog.h>

#include "planner/expr/expr_print.h"
#include "planner/verify/verify.h"

namespace ctb::solve {

namespace {

std::string Canonical(const Expr& e) {
  return PrintMiniZinc(e, [](const Expr& a) {
    std::string kind = a.var_kind == VarKind::kLocation      ? "L"
                       : a.var_kind == VarKind::kCommand     ? "U"
                       : a.var_kind == VarKind::kEpisodeState ? "EP"
                                                             : "TC";
    std::string idx = a.index.kind == IndexKind::kI       ? "i"
                      : a.index.kind == IndexKind::kIPlus1 ? "i+1"
                                                           : std::to_string(a.index.fixed);
    return kind + std::to_string(a.target) + "[" + idx + "]";
  });
}

std::string Canonical(const Condition& c) {
  return (c.info.IsChange() ? "change:" : "state:") + Canonical(c.expr);
}

Json Bound(const std::optional<double>& v) { return v ? Json(*v) : Json(nullptr); }

}  // namespace

std::string CanonicalForm(const Domain& d, const StatePlan& sp, Objective objective) {
  Json j;
  j["resolution"] = d.time_resolution;
  for (std::size_t a = 0; a < d.automata.size(); ++a) {
    const Automaton& au = d.automata[a];
    Json ja = {{"locations", au.locations.size()}, {"commands", au.commands.size()},
               {"initial", sp.initial[a]}};
    for (const auto& t : au.transitions)
      ja["transitions"].push_back({t.from, t.to, Canonical(t.guard), t.duration.lo,
                                   Bound(t.duration.hi), t.cost, t.controllable});
    j["automata"].push_back(ja);
  }
  j["maintenance"] = Canonical(sp.maintenance);
  j["goal"] = Canonical(sp.goal);
  for (const auto& e : sp.episodes)
    j["episodes"].push_back({Canonical(e.accepting), Canonical(e.state), e.lower, e.upper});
  for (const auto& t : sp.temporals)
    j["temporals"].push_back({Canonical(t.event1), Canonical(t.event2), t.lower, t.upper});
  for (const auto& ev : sp.events) {
    Json je = Json::array();
    for (const auto& x : ev.endpoints) je.push_back({static_cast<int>(x.kind), x.index});
    j["events"].push_back(je);
  }
  j["objective"] = ObjectiveName(objective);
  return j.dump();
}

namespace {

// One part solved and, where it claims optimality or infeasibility, checked against the relaxed
// runs in which idle events stand for other parts' events. nullopt: cannot be shown sound.
std::optional<Core> SolvePart(const SubProblem& part, const SolveOptions& po, Objective objective,
                              Clock::time_point t0, long time_limit_ms, Json& why) {
  SolveOptions o = po;
  o.time_limit_ms = std::max(1L, time_limit_ms - MsSince(t0));
  Core c = SolveOneModel(part.domain, part.plan, o);
  if (c.error) return c;
  SolveOptions relaxed = o;
  relaxed.idle_events = true;
  relaxed.time_limit_ms = std::max(1L, time_limit_ms - MsSince(t0));
  if (c.status == "infeasible") {
    // Infeasible in the part's own runs; the whole is infeasible only if the relaxed runs are.
    Core r = SolveOneModel(part.domain, part.plan, relaxed);
    c.runs += r.runs;
    if (r.error) return r;
    if (r.status == "infeasible") return c;
    why = "a part is infeasible alone but not with other parts' events";
    return std::nullopt;
  }
  if (c.status != "optimal" || !c.best) return c;
  Core stats;
  Refutation r = RefuteBetter(part.domain, part.plan, relaxed, *c.best, stats);
  c.runs += stats.runs;
  c.compile_ms += stats.compile_ms;
  if (stats.error) return stats;
  if (r == Refutation::kBetterExists) {
    why = "a part does better with other parts' events";
    return std::nullopt;
  }
  if (r == Refutation::kUnknown) c.status = "feasible";  // the time limit ended the proof
  return c;
}

}  // namespace

std::optional<Core> SolveParts(const Domain& d, const StatePlan& sp,
                               const std::vector<SubProblem>& parts, const SolveOptions& o,
                               Objective objective, Clock::time_point t0, Json& stats) {
  SolveOptions po = o;
  po.decompose = false;
  po.objective = objective;
  po.model_out.clear();
  std::vector<Trajectory> plans;
  std::map<std::string, Core> solved;  // canonical form -> result
  Core total;
  total.status = "optimal";
  int reused = 0;
  stats["parts"] = parts.size();
  for (const auto& part : parts) {
    std::string key = CanonicalForm(part.domain, part.plan, objective);
    Core c;
    if (auto it = solved.find(key); it != solved.end() && o.reuse_identical_parts) {
      c = it->second;
      ++reused;
    } else {
      Json why;
      auto r = SolvePart(part, po, objective, t0, o.time_limit_ms, why);
      if (!r) {
        stats["merge"] = why;
        spdlog::info("{}", Json("split not used: " + why.get<std::string>()).dump());
        return std::nullopt;
      }
      c = std::move(*r);
      if (c.error) return c;
      solved[key] = c;
      total.runs += c.runs;
      total.compile_ms += c.compile_ms;
      total.variables += c.variables;
    }
    if (c.status == "infeasible") {
      total.status = "infeasible";
      total.best.reset();
      stats["parts_reused"] = reused;
      return total;
    }
    if (!c.best) {
      total.status = "unknown";
      stats["parts_reused"] = reused;
      return total;
    }
    if (c.status != "optimal") total.status = "feasible";
    plans.push_back(c.best->traj);
  }
  stats["parts_reused"] = reused;
  Trajectory merged = MergeTrajectories(parts, plans, d, sp);
  const int limit = o.horizon ? *o.horizon : o.max_horizon;
  if (merged.goal_event > limit) {
    stats["merge"] = "too many events";
    return std::nullopt;
  }
  auto problems = VerifyTrajectory(merged, d, sp, std::lround(1.0 / d.time_resolution));
  if (!problems.empty()) {
    spdlog::info("{}", Json("merged plan failed verification (" + problems[0] +
                            "): solving as one model").dump(-1, ' ', false,
                                                            Json::error_handler_t::replace));
    stats["merge"] = "failed verification: " + problems[0];
    return std::nullopt;
  }
  total.best = Plan{merged, TrajectoryCost(merged, d), merged.events.back()};
  total.horizon = merged.goal_event;
  total.first_solution_ms = MsSince(t0);
  return total;
}

}  // namespace ctb::solve
