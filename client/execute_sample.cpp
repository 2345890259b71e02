#include "client/execute_sample.h"

#include <cmath>
#include <iostream>
#include <random>

#include "client/commands.h"
#include "planner/flexible/dispatch.h"
#include "planner/flexible/flexible.h"
#include "planner/model/catalog.h"
#include "planner/solve/solve.h"
#include "planner/verify/verify.h"

namespace ctb::cli {

namespace {

// A domain and a state plan from files; warnings go to stderr.
struct LoadedProblem {
  Domain domain;
  StatePlan sp;
};

std::variant<LoadedProblem, Error> LoadProblem(const std::string& domain, const std::string& config_dir,
                                               const std::string& file) {
  Diagnostics dd;
  auto d = LoadDomainByNameOrPath(domain, config_dir.empty() ? DefaultConfigDir() : config_dir, dd);
  if (!d) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid domain", dd);
  Diagnostics diags;
  auto json = ReadJsonFile(file, diags);
  std::optional<StatePlan> sp;
  if (json) sp = LoadStatePlan(*json, *d, diags);
  for (const auto& w : diags.warnings()) std::cerr << "warning: " << w.ToString() << "\n";
  if (!sp) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid state plan " + file, diags);
  return LoadedProblem{std::move(*d), std::move(*sp)};
}

struct Prepared {
  Trajectory plan;
  flexible::FlexiblePlan flex;
  std::vector<network::Ticks> planned;
};

// Solves the state plan and derives its network; an error message otherwise.
std::variant<Prepared, std::string> Prepare(const LoadedProblem& p, const SampleOptions& o) {
  SolveOptions so;
  so.time_limit_ms = o.time_limit_ms;
  if (!o.objective.empty()) so.objective = ParseObjective(o.objective);
  if (!o.controllability.empty()) so.controllability = *ParseControllability(o.controllability);
  Prepared out;
  so.plan_out = &out.plan;
  auto r = Solve(p.domain, p.sp, so);
  if (auto* e = std::get_if<Error>(&r)) return e->ToString();
  const SolveResult& a = std::get<SolveResult>(r);
  if (!a.verified()) return std::string("no plan to execute (status ") + TerminationName(a.status) + ")";
  if (a.status == Termination::kUnknown)
    return (a.message.empty() ? "no plan of the controllability asked for" : a.message) +
           " (--controllability none executes it anyway)";
  const long tps = std::lround(1.0 / p.domain.time_resolution);
  std::string why;
  auto f = flexible::DeriveNetwork(out.plan, p.domain, p.sp, tps, &why);
  if (!f) return why;
  out.flex = std::move(*f);
  out.planned = flexible::PlanTimes(out.flex, out.plan);
  return out;
}

}  // namespace

int RunSampledExecutions(const SampleOptions& o) {
  auto loaded = LoadProblem(o.domain, o.config_dir, o.file);
  if (auto* e = std::get_if<Error>(&loaded)) {
    PrintError(*e);
    return 1;
  }
  const LoadedProblem& p = std::get<LoadedProblem>(loaded);
  auto prepared = Prepare(p, o);
  if (auto* why = std::get_if<std::string>(&prepared)) {
    std::cerr << "error: " << *why << "\n";
    return 3;
  }
  const Prepared& pr = std::get<Prepared>(prepared);
  const long tps = pr.flex.tps;
  flexible::DispatchOptions d;
  d.dynamic = o.dispatch == "dynamic";
  d.sampling = o.sample == "distribution" ? flexible::Sampling::kDistribution : flexible::Sampling::kUniform;
  std::mt19937 rng(o.seed);
  int succeeded = 0;
  for (int run = 0; run < o.runs; ++run) {
    flexible::Execution e = flexible::Execute(pr.flex, p.domain, pr.planned, d, rng);
    std::string why = e.why;
    std::optional<Trajectory> t;
    if (e.met) t = flexible::ScheduleToTrajectory(pr.flex, pr.plan, e.times, &why);
    std::vector<std::string> problems;
    if (t) problems = VerifyTrajectory(*t, p.domain, p.sp, tps);
    const bool ok = e.met && t && problems.empty();
    succeeded += ok ? 1 : 0;
    if (!o.json) continue;
    Json line = {{"run", run}, {"succeeded", ok}};
    if (t) line["trajectory"] = TrajectoryToJson(*t, p.domain, p.sp, tps);
    if (!ok) line["why"] = problems.empty() ? why : problems.front();
    std::cout << line.dump() << "\n";
  }
  std::cout << Json({{"runs", o.runs}, {"succeeded", succeeded}, {"violated", o.runs - succeeded}})
                   .dump()
            << std::endl;
  return succeeded == o.runs ? 0 : 5;
}

}  // namespace ctb::cli
