#include "planner/solve/parts.h"

#include <cmath>
#include <map>

#include <spdlog/spdlog.h>

#include "planner/expr/expr_print.h"
#include "planner/analyze/bounds.h"
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

// A part solved on its own runs. An infeasible part is checked against the relaxed runs in which
// idle events stand for other parts' events. nullopt: the split cannot be shown sound.
std::optional<Core> SolveAlone(const SubProblem& part, const SolveOptions& po,
                               Clock::time_point t0, long time_limit_ms, std::string& why) {
  SolveOptions o = po;
  o.time_limit_ms = std::max(1L, time_limit_ms - MsSince(t0));
  Core c = SolveOneModel(part.domain, part.plan, o);
  if (c.error || c.status != Termination::kInfeasible) return c;
  SolveOptions relaxed = o;
  relaxed.idle_events = true;
  relaxed.time_limit_ms = std::max(1L, time_limit_ms - MsSince(t0));
  Core r = SolveOneModel(part.domain, part.plan, relaxed);
  c.runs += r.runs;
  AddEngine(c.engine, r.engine);
  if (r.error) return r;
  if (r.status == Termination::kInfeasible) return c;
  why = "a part is infeasible alone but not with other parts' events";
  return std::nullopt;
}

// Proves that no relaxed run of the part beats its plan. false: one does (the split is not
// sound for this problem); an unfinished proof leaves the part "feasible".
bool ProveAgainstRelaxedRuns(const SubProblem& part, const SolveOptions& po, Clock::time_point t0,
                             long time_limit_ms, Core& c) {
  SolveOptions relaxed = po;
  relaxed.idle_events = true;
  relaxed.time_limit_ms = std::max(1L, time_limit_ms - MsSince(t0));
  Core stats;
  Refutation r = RefuteBetter(part.domain, part.plan, relaxed, *c.best, stats);
  c.runs += stats.runs;
  c.compile_ms += stats.compile_ms;
  AddEngine(c.engine, stats.engine);
  if (stats.error) {
    c.error = stats.error;
    return true;
  }
  if (r == Refutation::kBetterExists) return false;
  if (r == Refutation::kUnknown) c.status = Termination::kFeasible;
  return true;
}

}  // namespace

std::optional<Core> SolveParts(const Domain& d, const StatePlan& sp,
                               const std::vector<SubProblem>& parts, const SolveOptions& o,
                               Objective objective, Clock::time_point t0, Json& stats) {
  SolveOptions po = o;
  po.decompose = false;
  po.objective = objective;
  po.model_out.clear();
  po.on_progress = nullptr;  // a part's objective is not the whole plan's
  stats["parts"] = parts.size();
  auto give_up = [&](const std::string& why) {
    stats["merge"] = why;
    spdlog::info("{}", Json("split not used: " + why).dump());
    return std::nullopt;
  };
  // Phase 1: each distinct part on its own runs (identical parts once).
  std::vector<std::string> keys;
  std::map<std::string, Core> solved;
  std::map<std::string, const SubProblem*> first_of;
  Core total;
  total.status = Termination::kOptimal;
  int reused = 0;
  for (const auto& part : parts) {
    std::string key = CanonicalForm(part.domain, part.plan, objective);
    if (!o.reuse_identical_parts) key += "#" + std::to_string(keys.size());
    keys.push_back(key);
    if (solved.count(key)) {
      ++reused;
      continue;
    }
    std::string why;
    auto c = SolveAlone(part, po, t0, o.time_limit_ms, why);
    if (!c) return give_up(why);
    if (c->error) return c;
    total.runs += c->runs;
    total.compile_ms += c->compile_ms;
    AddEngine(total.engine, c->engine);
    total.variables += c->variables;
    stats["parts_reused"] = reused;
    if (c->status == Termination::kInfeasible || !c->best) {
      total.status = c->status == Termination::kInfeasible ? Termination::kInfeasible : Termination::kUnknown;
      return total;
    }
    solved[key] = std::move(*c);
    first_of[key] = &part;
  }
  stats["parts_reused"] = reused;
  // Phase 2: prove each part's share against the relaxed runs, where it counts. A plan that
  // meets the part's lower bound needs no proof; for makespan only the parts that reach the
  // latest goal time count (the others need not be optimal).
  long latest = 0;
  for (auto& [key, c] : solved) latest = std::max(latest, c.best->makespan);
  for (auto& [key, c] : solved) {
    if (c.status != Termination::kOptimal) continue;
    if (objective == Objective::kMakespan && c.best->makespan < latest) continue;
    const SubProblem& part = *first_of[key];
    if (MeetsLowerBounds(LowerBounds(part.domain, part.plan, CostBoundsFor(objective)), objective,
                         c.best->cost,
                         c.best->makespan))
      continue;
    if (!ProveAgainstRelaxedRuns(*first_of[key], po, t0, o.time_limit_ms, c))
      return give_up("a part does better with other parts' events");
    if (c.error) return c;
  }
  std::vector<Trajectory> plans;
  for (const auto& key : keys) {
    const Core& c = solved[key];
    if (c.status != Termination::kOptimal) total.status = Termination::kFeasible;
    plans.push_back(c.best->traj);
  }
  Trajectory merged = MergeTrajectories(parts, plans, d, sp);
  const int limit = o.horizon ? *o.horizon : o.max_horizon;
  if (merged.goal_event > limit) return give_up("too many events");
  auto problems = VerifyTrajectory(merged, d, sp, std::lround(1.0 / d.time_resolution));
  if (!problems.empty()) return give_up("failed verification: " + problems[0]);
  total.best = Plan{merged, TrajectoryCost(merged, d), merged.events.back()};
  total.horizon = merged.goal_event;
  total.first_solution_ms = MsSince(t0);
  return total;
}

}  // namespace ctb::solve
