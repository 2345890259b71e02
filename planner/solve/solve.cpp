#include "planner/solve/solve.h"

#include <cmath>
#include <fstream>

#include "planner/analyze/analyze.h"
#include "planner/encode/encoder.h"
#include "planner/solve/backend.h"
#include "planner/analyze/bounds.h"
#include "planner/solve/decompose.h"
#include "planner/solve/engines.h"
#include "planner/solve/controllable.h"
#include "planner/solve/flexible_answer.h"
#include "planner/solve/horizon_solver.h"
#include "planner/solve/incumbent.h"
#include "planner/solve/parts.h"

namespace ctb {

using solve::Clock;
using solve::Core;
using solve::SolveOneModel;
using solve::SolveParts;

namespace {

// --model-out when no exact engine ran (the first plan met the lower bound, or the parts were
// solved apart): the whole problem's model at the plan's horizon, so the file always exists.
void WriteModelOut(const Domain& d, const StatePlan& sp, const SolveOptions& o, Objective objective,
                   int horizon) {
  if (o.model_out.empty()) return;
  EncodeOptions eo;
  eo.horizon = std::max(1, horizon);
  eo.objective = objective;
  eo.redundant = o.redundant;
  eo.symmetry = o.symmetry;
  eo.history = o.history.get();
  ProblemInfo info = Analyze(d, sp);
  if (o.symmetry && !o.history) info.symmetries = FindSymmetries(d, sp);
  if (o.history) info.time_offset = o.history->now;  // as the horizon search's models
  Encoding enc = Encode(d, sp, info, eo);
  std::ofstream(o.model_out) << enc.model;
  std::ofstream(o.model_out + ".json") << enc.data.dump(1) << "\n";
}

SolveResult ResultOf(const Domain& d, const StatePlan& sp, Objective objective, const Core& c,
                     int max_horizon, long elapsed_ms, const Json& extra_stats,
                     const std::string& solver_name,
                     const std::optional<ObjectiveBounds>& bounds = std::nullopt,
                     Trajectory* plan_out = nullptr) {
  SolveResult r;
  r.status = c.status;
  r.objective = objective;
  r.ticks_per_second = std::lround(1.0 / d.time_resolution);
  if (plan_out && c.best) *plan_out = c.best->traj;
  if (c.best) {
    r.plan = c.best->traj;
    r.cost = c.best->cost;
    r.makespan_ticks = c.best->makespan;
  }
  r.horizon = c.horizon;
  r.max_horizon = max_horizon;
  // How far from optimal the plan may be: a bound every plan obeys.
  if (c.status == Termination::kFeasible)
    r.bound = BoundValue(bounds ? *bounds : LowerBounds(d, sp, CostBoundsFor(objective)), objective,
                         r.ticks_per_second);
  // Which engine found the plan and what proved the status.
  const std::string engine = c.engine.empty() ? solver_name : c.engine;
  r.stats.solver = engine;
  r.stats.found_by = c.found_by.empty() ? ByEngine(engine) : c.found_by;
  r.stats.proved_by = c.proved_by.empty() ? ByEngine(engine) : c.proved_by;
  r.stats.compile_ms = c.compile_ms;
  r.stats.solve_ms = elapsed_ms;
  r.stats.first_solution_ms = c.first_solution_ms;
  r.stats.variables = c.variables;
  r.stats.solver_runs = c.runs;
  r.stats.extra = extra_stats;
  return r;
}

// A solver's infeasible holds for at most max_horizon events (the horizon search's bound).
SolveResult WithScope(SolveResult r) {
  if (r.status == Termination::kInfeasible) r.scope = InfeasibleScope::kMaxHorizon;
  return r;
}

}  // namespace

std::optional<Error> ValidateSolveOptions(const SolveOptions& o) {
  Diagnostics d;
  if (o.horizon && (*o.horizon < 0 || *o.horizon > kMaxHorizonLimit))
    d.Error("/options/horizon", "horizon must be between 0 and " + std::to_string(kMaxHorizonLimit));
  if (o.max_horizon < 0 || o.max_horizon > kMaxHorizonLimit)
    d.Error("/options/max_horizon", "max_horizon must be between 0 and " + std::to_string(kMaxHorizonLimit));
  if (o.time_limit_ms < 1 || o.time_limit_ms > 3600 * 1000)
    d.Error("/options/time_limit_ms", "time_limit_ms must be between 1 and 3,600,000");
  if (o.threads < 1 || o.threads > 64) d.Error("/options/threads", "threads must be between 1 and 64");
  if (o.search != "portfolio" && !solve::FindEngine(o.search))
    d.Error("/options/search", "search must be one of " + solve::SearchNames());
  if (o.first_plan_ms < -1 || o.first_plan_ms > 3600 * 1000)
    d.Error("/options/first_plan_ms", "first_plan_ms must be -1 (automatic) or between 0 and "
                                      "3,600,000");
  if (o.zone_proof_ms < -1 || o.zone_proof_ms > 3600 * 1000)
    d.Error("/options/zone_proof_ms", "zone_proof_ms must be -1 (automatic) or between 0 and "
                                      "3,600,000");
  if (o.portfolio < 1 || o.portfolio > 3)
    d.Error("/options/portfolio", "portfolio must be 1, 2 or 3");
  if (d.ok()) return std::nullopt;
  return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid solve options", d);
}

std::optional<Error> CheckRepresentable(const Domain& d, const StatePlan& sp, Objective objective,
                                        int max_horizon) {
  const ProblemInfo info = Analyze(d, sp);
  const long double h = std::max(1, max_horizon);
  const long double t = static_cast<long double>(info.TimeBound(max_horizon));
  long max_cost = 0;
  std::string cost_ptr = "/options/max_horizon", time_ptr = "/options/max_horizon";
  double longest = -1;
  for (const auto& a : d.automata)
    for (const auto& tr : a.transitions) {
      if (tr.cost > max_cost) {
        max_cost = tr.cost;
        cost_ptr = tr.pointer + "/cost";
      }
      if (tr.duration.lo > longest) {
        longest = tr.duration.lo;
        time_ptr = tr.pointer + "/duration";
      }
    }
  for (const auto& ep : sp.episodes)
    if (ep.lower > longest) {
      longest = ep.lower;
      time_ptr = ep.accepting.pointer.substr(0, ep.accepting.pointer.rfind('/')) + "/lower_bound";
    }
  const long double cost = static_cast<long double>(d.automata.size()) * max_cost * h;
  long double objective_max = objective == Objective::kCost       ? cost
                              : objective == Objective::kMakespan ? t
                                                                  : cost * (t + 1) + t;
  auto fail = [&](const std::string& ptr, const std::string& what, long double v) {
    Diagnostics diags;
    diags.Error(ptr, what + " may reach " + std::to_string(static_cast<long long>(v)) +
                         ", beyond the solver's integer range (" + std::to_string(kSolverIntMax) +
                         "); use smaller costs, durations or bounds, a coarser time_resolution, "
                         "or a smaller max_horizon");
    return Error::FromDiagnostics(ErrorCode::kInvalidInput, "the problem cannot be represented "
                                  "in the solver's integers", diags);
  };
  if (t > kSolverIntMax) return fail(time_ptr, "the time bound (in ticks)", t);
  if (objective_max > kSolverIntMax)
    return fail(objective == Objective::kMakespan ? time_ptr : cost_ptr, "the objective", objective_max);
  return std::nullopt;
}

namespace {

// The domain whose forbidden transitions (contract section 15) can never fire: a plan that never
// takes them is a run of it, so it relaxes the problem and its analyses (static conflicts, lower
// bounds) are sound for it, and tighter. (Its own runs may still break the rule, where a
// forbidden automatic transition would be due: plans are found on `d` and verified.)
Domain WithoutForbidden(const Domain& d, const StatePlan& sp) {
  Domain out = d;
  for (int j : sp.forbidden) {
    const ActionEvent& act = sp.actions[j];
    for (int ti : act.transitions) {
      Transition& tr = out.automata[act.automaton].transitions[ti];
      tr.guard = Expr{};
      tr.guard.op = Expr::Op::kFalse;
      tr.guard_info = ExprInfo{};
      tr.guard_text = "false";
    }
  }
  return out;
}

// Solve with every duration the planner's or fixed (no contingent transition left in d).
std::variant<SolveResult, Error> SolveFixed(const Domain& d, const StatePlan& sp, const SolveOptions& o,
                                     const Domain* analysis = nullptr);

std::variant<SolveResult, Error> SolveForbidding(const Domain& d, const StatePlan& sp, const SolveOptions& o) {
  const Domain without = WithoutForbidden(d, sp);
  SolveOptions with = o;
  with.bounds = LowerBounds(without, sp, CostBoundsFor(o.objective.value_or(sp.objective)));
  return SolveFixed(d, sp, with, &without);
}

long ZoneProofBudgetMs(const SolveOptions& o) {
  if (o.zone_proof_ms >= 0) return o.zone_proof_ms;
  return std::min(2000L, o.time_limit_ms / 5);
}

// Makespan: the zone search with a deadline (analyze/bounds.h) on the plan's makespan less a
// tick, within its budget and the time left; raises `bounds` to what it shows. True when the
// plan now meets it (optimal).
bool RaiseBoundByZones(const Domain& d, const StatePlan& sp, const SolveOptions& o,
                       ObjectiveBounds& bounds, long plan_ticks, Clock::time_point t0,
                       Json& stats) {
  MakespanProofBudget budget;
  budget.ms = std::min(ZoneProofBudgetMs(o), o.time_limit_ms - MsSince(t0));
  budget.cancel = o.cancel;
  if (budget.ms <= 0) return false;
  const long before = bounds.makespan_ticks;
  MakespanProof p = RaiseMakespanBound(d, sp, before, plan_ticks, budget);
  if (p.searches == 0) return false;
  stats["zone_bound"] = {{"ms", p.ms}, {"searches", p.searches}, {"states", p.states},
                         {"raised", p.makespan_ticks > before}};
  bounds.makespan_ticks = std::max(before, p.makespan_ticks);
  return bounds.makespan_ticks >= plan_ticks;
}

std::variant<SolveResult, Error> SolveFixed(const Domain& d, const StatePlan& sp, const SolveOptions& o,
                                     const Domain* analysis) {
  if (!analysis && !sp.forbidden.empty() && !o.bounds && !o.history) return SolveForbidding(d, sp, o);
  if (auto e = ValidateSolveOptions(o)) return *e;
  const auto t0 = Clock::now();
  const Objective objective = o.objective.value_or(sp.objective);
  const int max_h = o.horizon ? *o.horizon : o.max_horizon;
  if (auto e = CheckRepresentable(d, sp, objective, max_h)) return *e;
  const solve::Engine* alone = solve::FindEngine(o.search);
  SolverBackend& gecode = o.backend ? *o.backend : DefaultBackend();
  const std::string solver = alone ? solve::BackendOf(*alone, gecode).Name() : gecode.Name();
  Json stats = Json::object();
  if (o.static_analysis && !o.history) {
    // A proof of infeasibility without search (planner/analyze): every check over-approximates
    // the runs, so a conflict holds whatever the horizon.
    if (auto conflict = FindStaticConflict(analysis ? *analysis : d, sp)) {
      Core c;
      c.status = Termination::kInfeasible;
      c.proved_by = {Method::kStaticAnalysis, ""};
      stats["static_conflict"] = conflict->text;
      SolveResult out = ResultOf(d, sp, objective, c, max_h, MsSince(t0), stats, "static analysis");
      out.scope = InfeasibleScope::kAnyHorizon;
      return out;
    }
  }
  // The first-plan engine (planner/search): a verified plan in milliseconds, streamed first and
  // handed to the exact engines as the incumbent; optimal at once when it meets the lower bound.
  // A problem that splits is solved part by part, each small and fast: the engine's plan of the
  // whole would not help them, so it runs on problems solved as one model only.
  std::vector<SubProblem> parts;
  if (o.decompose && !o.history) parts = SplitProblem(d, sp);
  long found_ms = -1;
  std::optional<solve::Plan> incumbent;
  bool meets_bound = false;
  // The lower bounds are computed once, when first needed (the first-plan engine's target, the
  // exact engines' closing rule, the answer's bound): at a thousand automata they are a tenth of
  // the solve.
  std::optional<ObjectiveBounds> known_bounds = o.bounds;
  auto bounds_of_whole = [&]() -> const ObjectiveBounds& {
    if (!known_bounds) known_bounds = LowerBounds(d, sp, CostBoundsFor(objective));
    return *known_bounds;
  };
  // Replanning (o.history): the engine starts from the history; the bounds are those valid given
  // it (o.bounds), so a plan that meets them is optimal for the future as for the exact engines.
  if (!o.idle_events && solve::FirstPlanBudgetMs(o) > 0 && parts.size() <= 1) {
    const ObjectiveBounds& bounds = bounds_of_whole();
    incumbent = solve::FirstPlanIncumbent(d, sp, o, objective, max_h, bounds, t0, stats, found_ms);
    meets_bound = incumbent &&
                  MeetsLowerBounds(bounds, objective, incumbent->cost, incumbent->makespan);
  }
  bool by_zones = false;
  if (incumbent && !meets_bound && objective == Objective::kMakespan && !o.history) {
    // On the domain analysed (forbidden transitions kept: more runs, still every plan's).
    by_zones = RaiseBoundByZones(analysis ? *analysis : d, sp, o, *known_bounds,
                                 incumbent->makespan, t0, stats);
    meets_bound = by_zones;
  }
  if (meets_bound) {
    Core c;
    c.status = Termination::kOptimal;
    c.best = incumbent;
    c.horizon = incumbent->traj.goal_event;
    c.first_solution_ms = found_ms;
    c.engine = "heuristic";
    c.found_by = {Method::kHeuristic, ""};
    c.proved_by = {by_zones ? Method::kZoneSearch : Method::kLowerBound, ""};
    WriteModelOut(d, sp, o, objective, c.horizon);
    return ResultOf(d, sp, objective, c, max_h, MsSince(t0), stats, solver, bounds_of_whole(),
                    o.plan_out);
  }
  if (parts.size() > 1) {
    auto c = SolveParts(d, sp, parts, o, objective, t0, stats);
    if (c && c->error) return *c->error;
    if (c) {
      WriteModelOut(d, sp, o, objective, c->best ? c->best->traj.goal_event : c->horizon);
      return WithScope(ResultOf(d, sp, objective, *c, max_h, MsSince(t0), stats, solver,
                                known_bounds, o.plan_out));
    }
  }
  SolveOptions mono = o;
  mono.bounds = bounds_of_whole();
  const long offset = MsSince(t0);
  mono.time_limit_ms = std::max(1L, o.time_limit_ms - offset);
  if (o.on_progress)
    mono.on_progress = [&o, offset](const SolveProgress& p) {
      SolveProgress q = p;
      q.elapsed_ms += offset;  // since the solve began
      o.on_progress(q);
    };
  Core c = SolveOneModel(d, sp, mono, incumbent);
  if (c.error) return *c.error;
  if (c.first_solution_ms >= 0) c.first_solution_ms += offset;
  if (found_ms >= 0) c.first_solution_ms = found_ms;
  return WithScope(
      ResultOf(d, sp, objective, c, max_h, MsSince(t0), stats, solver, known_bounds, o.plan_out));
}

}  // namespace

const char* ControllabilityName(Controllability c) {
  switch (c) {
    case Controllability::kAuto: return "auto";
    case Controllability::kDynamic: return "dynamic";
    case Controllability::kStrong: return "strong";
    case Controllability::kNone: return "none";
  }
  return "auto";
}

std::optional<Controllability> ParseControllability(const std::string& s) {
  for (auto c : {Controllability::kAuto, Controllability::kDynamic, Controllability::kStrong,
                 Controllability::kNone})
    if (s == ControllabilityName(c)) return c;
  return std::nullopt;
}

// Contingent transitions are planned for at their longest duration (the worst case) or, with
// controllability "none", as the planner's choice; the plan's network then carries them as
// contingent links (planner/flexible, solve/flexible_answer.cpp).
// A plan that is not of the asked kind is cut and the next best one planned (solve/controllable.h).
std::variant<SolveResult, Error> Solve(const Domain& d, const StatePlan& sp, const SolveOptions& o) {
  const solve::FixedSolve fixed = [](const Domain& written, const StatePlan& s,
                                     const SolveOptions& so) -> std::variant<SolveResult, Error> {
    if (!written.HasContingent()) return SolveFixed(written, s, so);
    return SolveFixed(PlanningDomain(written, so.controllability == Controllability::kNone), s, so);
  };
  return solve::SolveControllable(d, sp, o, fixed);
}

std::variant<Json, Error> SolveDocument(const Domain& d, const StatePlan& sp, const SolveOptions& o) {
  auto r = Solve(d, sp, o);
  if (auto* e = std::get_if<Error>(&r)) return *e;
  return ResultJson(std::get<SolveResult>(r), d, sp);
}

}  // namespace ctb
