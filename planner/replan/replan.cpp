#include "planner/model/elapsed.h"
#include "planner/replan/replan.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "planner/encode/encoder.h"
#include "planner/encode/extract.h"
#include "planner/replan/diff.h"
#include "planner/replan/precheck.h"
#include "planner/replan/situation.h"
#include "planner/solve/backend.h"
#include "planner/verify/verify.h"

namespace ctb {

using replan::Situation;

const char* KeepName(Keep k) {
  switch (k) {
    case Keep::kNone: return "none";
    case Keep::kStarted: return "started";
    case Keep::kMinChange: return "min_change";
  }
  return "none";
}

std::optional<Keep> ParseKeep(const std::string& s) {
  if (s == "none") return Keep::kNone;
  if (s == "started") return Keep::kStarted;
  if (s == "min_change") return Keep::kMinChange;
  return std::nullopt;
}

std::optional<Error> ReadReplanRequest(const Json& body, ReplanRequest& out, Keep* keep) {
  Diagnostics diags;
  if (!body.is_object()) {
    diags.Error("", "the request must be a JSON object");
    return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid replanning request", diags);
  }
  auto field = [&](const char* k) { return body.contains(k) ? body[k] : Json(); };
  out.now = field("now");
  if (out.now.is_null()) diags.Error("/now", "now (seconds since the plan started) is required");
  out.executed = field("executed");
  out.observed = field("observed");
  out.blocked = field("blocked");
  out.previous = field("trajectory");
  out.previous_pointer = "/trajectory";
  if (keep && body.contains("options") && body["options"].is_object() &&
      body["options"].contains("keep")) {
    const Json& k = body["options"]["keep"];
    auto parsed = k.is_string() ? ParseKeep(k.get<std::string>()) : std::nullopt;
    if (!parsed)
      diags.Error("/options/keep", "keep must be \"none\", \"started\" or \"min_change\"");
    else
      *keep = *parsed;
  }
  if (diags.ok()) return std::nullopt;
  return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid replanning request", diags);
}

namespace {

using Clock = std::chrono::steady_clock;

Json Seconds(long ticks, long tps) {
  if (tps == 1) return ticks;
  return static_cast<double>(ticks) / static_cast<double>(tps);
}

// An infeasible answer decided before any solve: the history already broke the state plan, or
// what is blocked cuts the goal off, whatever the number of events.
SolveResult Infeasible(Objective objective, std::vector<ExplanationConflict> conflicts,
                       const Situation& s, long ms, Method why, int max_horizon) {
  SolveResult r;
  r.status = Termination::kInfeasible;
  r.objective = objective;
  r.ticks_per_second = s.tps;
  r.horizon = s.history.events();
  r.max_horizon = max_horizon;
  r.scope = InfeasibleScope::kAnyHorizon;
  r.explanation = Explanation{std::move(conflicts), {}, ExplanationStatus::kMinimal, std::nullopt,
                              Json(), ""};
  r.stats.proved_by = {why, ""};
  r.stats.solver = r.stats.proved_by.Name();
  r.stats.solve_ms = ms;
  return r;
}

// keep "min_change": a second solve, among plans at most as good as the optimum, for the fewest
// changes, at the optimum's horizon or where the previous plan's future fits, whichever is more
// (the first-plan engine's optimum may have fewer events than the previous plan). Replaces the
// answer's plan when it finds one with fewer changes.
void MinimiseChanges(const Domain& md, const Domain& d, const StatePlan& sp, const Situation& s,
                     const SolveOptions& so, long time_left_ms, SolveResult& ans) {
  if (!ans.plan || time_left_ms <= 0) return;
  const Objective objective = ans.objective;
  const int H = std::min(so.max_horizon, std::max(ans.plan->horizon,
                                                  s.history.events() + s.previous_future_events));
  ProblemInfo info = Analyze(md, sp);
  info.time_offset = s.history.now;
  auto [cf, mf] = ObjectiveFactors(objective, info.TimeBound(H));
  EncodeOptions eo;
  eo.horizon = H;
  eo.objective = objective;
  eo.history = so.history.get();
  eo.minimize_changes = true;
  eo.objective_at_most = ans.cost * cf + ans.makespan_ticks * mf;
  for (const auto& p : s.baseline)
    eo.baseline.emplace_back(info.transitions_of[p.automaton][p.transition], p.time);
  Encoding enc = Encode(md, sp, info, eo);
  RunRequest req;
  req.model = std::move(enc.model);
  req.data = std::move(enc.data);
  req.time_limit_ms = time_left_ms;
  req.minizinc = so.minizinc;
  req.memory_limit_mb = so.memory_limit_mb;
  req.cancel = so.cancel;
  RunResult r = DefaultBackend().Run(req);
  ans.stats.extra["min_change_status"] = RunStatusName(r.status);
  if (!r.best) return;
  std::string why;
  auto traj = ExtractTrajectory(*r.best, md, sp, H, why);
  if (!traj) return;
  traj->history = so.history;
  if (!VerifyTrajectory(*traj, md, sp, s.tps).empty()) {
    ans.stats.extra["min_change_status"] = "unverified";  // never returned
    return;
  }
  const Json before = replan::DiffAgainstPrevious(*ans.plan, d, s);
  const Json after = replan::DiffAgainstPrevious(*traj, d, s);
  if (replan::Changes(after) >= replan::Changes(before)) return;
  ans.cost = TrajectoryCost(*traj, md);
  ans.makespan_ticks = traj->events[traj->goal_event];
  ans.plan = std::move(*traj);
}

}  // namespace

std::optional<Error> CheckReplanRequest(const Domain& d, const StatePlan& sp,
                                        const ReplanRequest& req) {
  replan::Situation s;
  return replan::BuildSituation(d, sp, req, Keep::kNone, s);
}

std::variant<ReplanResult, Error> Replan(const Domain& d, const StatePlan& sp,
                                         const ReplanRequest& req, const ReplanOptions& o) {
  const auto t0 = Clock::now();
  if (o.solve.horizon) {
    Diagnostics diags;
    diags.Error("/options/horizon", "a replan grows its horizon; use max_horizon (the most events "
                                    "of the future)");
    return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid replanning options", diags);
  }
  if (auto e = ValidateSolveOptions(o.solve)) return *e;
  Situation s;
  if (auto e = replan::BuildSituation(d, sp, req, o.keep, s)) return *e;
  const int p = s.history.events();
  const Objective objective = o.solve.objective.value_or(sp.objective);
  if (p + 1 > kMaxHorizonLimit) {
    Diagnostics diags;
    diags.Error("/executed", "the history has " + std::to_string(p) + " events; at most " +
                                 std::to_string(kMaxHorizonLimit - 1) + " are supported");
    return Error::FromDiagnostics(ErrorCode::kInvalidInput, "history too long", diags);
  }
  const int max_h = std::min(kMaxHorizonLimit, p + o.solve.max_horizon);
  if (o.precheck) {
    std::vector<ExplanationConflict> broken = replan::BrokenByHistory(sp, s);
    auto early = [&](std::vector<ExplanationConflict> conflicts, Method why) {
      ReplanResult r;
      r.answer = Infeasible(objective, std::move(conflicts), s, MsSince(t0), why, max_h);
      r.answer.stats.extra["history_events"] = p;
      r.now_ticks = s.history.now;
      r.keep = o.keep;
      return r;
    };
    if (!broken.empty()) return early(broken, Method::kHistoryCheck);
    if (auto cut = replan::GoalCutOff(d, sp, s)) return early({*cut}, Method::kStaticAnalysis);
  }
  SolveOptions so = o.solve;
  so.history = std::make_shared<const History>(s.history);
  so.bounds = replan::HistoryBounds(sp, s);
  so.static_analysis = false;
  so.decompose = false;
  so.max_horizon = max_h;
  // The previous plan's future usually fits again: start the horizon there (a larger model holds
  // every smaller plan, so this loses nothing).
  so.first_horizon = p + s.previous_future_events;
  auto solved = Solve(s.model_domain, sp, so);
  if (auto* e = std::get_if<Error>(&solved)) return *e;
  ReplanResult out;
  out.answer = std::get<SolveResult>(std::move(solved));
  SolveResult& ans = out.answer;
  if (ans.status == Termination::kInfeasible && !ans.explanation) {
    std::string text = "no future from the state at t = " + Seconds(s.history.now, s.tps).dump() +
                       " s satisfies the state plan with at most " +
                       std::to_string(o.solve.max_horizon) + " more events";
    if (!s.history.keep_next.empty()) text += " (keep: started holds every started transition)";
    ExplanationConflict conflict{{}, text, Json()};
    if (auto cut = replan::GoalCutOff(d, sp, s)) conflict = *cut;
    Explanation ex;
    ex.status = conflict.constraints.empty() ? ExplanationStatus::kUnknown : ExplanationStatus::kMinimal;
    ex.conflicts.push_back(std::move(conflict));
    ans.explanation = std::move(ex);
  }
  if (o.keep == Keep::kMinChange && s.have_previous && ans.plan)
    MinimiseChanges(s.model_domain, d, sp, s, so, o.solve.time_limit_ms - MsSince(t0), ans);
  out.now_ticks = s.history.now;
  out.keep = o.keep;
  ans.stats.extra["history_events"] = p;
  if (ans.plan) out.diff = replan::DiffAgainstPrevious(*ans.plan, d, s);
  ans.stats.solve_ms = MsSince(t0);
  return out;
}

Json ReplanJson(const ReplanResult& r, const Domain& d, const StatePlan& sp) {
  Json out = ResultJson(r.answer, d, sp);
  out["now"] = Seconds(r.now_ticks, r.answer.ticks_per_second);
  out["keep"] = KeepName(r.keep);
  if (r.diff) out["diff"] = *r.diff;
  return out;
}

std::variant<Json, Error> ReplanDocument(const Domain& d, const StatePlan& sp,
                                         const ReplanRequest& req, const ReplanOptions& o) {
  auto r = Replan(d, sp, req, o);
  if (auto* e = std::get_if<Error>(&r)) return *e;
  return ReplanJson(std::get<ReplanResult>(r), d, sp);
}

}  // namespace ctb
