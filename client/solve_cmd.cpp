#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>

#include "client/commands.h"
#include "client/remote.h"
#include "client/local_core.h"
#include "interchange/pddl/import.h"
#include "planner/model/catalog.h"
#include "planner/solve/solve.h"

namespace ctb::cli {

namespace {
struct SolveCliOptions {
  std::string domain, file, config_dir, objective, controllability;
  std::optional<double> risk_bound;
  long time_limit_ms = 60000;
  std::optional<int> horizon;
  int max_horizon = 32;
  int threads = 1;
  std::string search = "portfolio";
  int portfolio = 2;
  bool no_decompose = false;
  bool no_reuse = false;
  bool no_redundant = false;
  long first_plan_ms = -1;
  long zone_proof_ms = -1;
  std::string model_out;
  std::string server;
  std::string pddl_plan;                 // write the plan here as PDDL 2.1
  bool compact = false;                  // the answer as HTTP sends it (one line)
  bool max_horizon_given = false;
  std::vector<std::string> pddl_files;  // the PDDL domain (and problem) the model came from
};

// --pddl-plan: imports the PDDL again (the same names as `domain import-pddl` gave) and writes the
// trajectory as a PDDL 2.1 plan. False (with the reason on stderr) when that cannot be done.
bool WritePddlPlan(const SolveCliOptions& o, const Json& trajectory) {
  std::vector<pddl::Source> sources;
  for (const auto& f : o.pddl_files) {
    std::ifstream in(f);
    std::ostringstream text;
    text << in.rdbuf();
    if (!in) {
      std::cerr << "error: cannot read " << f << "\n";
      return false;
    }
    sources.push_back(pddl::Source{f, text.str()});
  }
  std::optional<pddl::Source> problem;
  if (sources.size() > 1) problem = sources[1];
  auto r = pddl::ImportPddl(sources[0], problem);
  if (auto* issues = std::get_if<std::vector<pddl::Issue>>(&r)) {
    std::cerr << "error: --pddl: " << (issues->empty() ? "" : (*issues)[0].ToString()) << "\n";
    return false;
  }
  std::ofstream out(o.pddl_plan);
  out << pddl::PddlPlan(trajectory, std::get<pddl::Imported>(r).actions);
  if (!out) std::cerr << "error: cannot write " << o.pddl_plan << "\n";
  return static_cast<bool>(out);
}

// Without --domain, `--pddl DOMAIN PROBLEM` imported here (the core's PDDL import, as `domain
// import-pddl` does): the model, the state plan and the actions' names, with no JSON file between.
struct DirectPddl {
  Json action_model, state_plan;
  std::vector<pddl::PlanAction> actions;
};

std::optional<DirectPddl> ImportForSolve(app::Core& core, const SolveCliOptions& o) {
  app::PddlImportCall call;
  for (std::size_t k = 0; k < o.pddl_files.size(); ++k) {
    std::ifstream in(o.pddl_files[k]);
    std::ostringstream text;
    text << in.rdbuf();
    if (!in) {
      std::cerr << "error: cannot read " << o.pddl_files[k] << "\n";
      return std::nullopt;
    }
    (k == 0 ? call.domain : call.problem) = text.str();
  }
  auto r = core.ImportPddl(call);
  if (auto* e = std::get_if<Error>(&r)) {
    for (const auto& d : e->details) std::cerr << "error: " << d.message << "\n";
    if (e->details.empty()) std::cerr << "error: " << e->message << "\n";
    return std::nullopt;
  }
  auto& im = std::get<app::PddlImportAnswer>(r);
  for (const auto& w : im.warnings) std::cerr << "warning: " << w.value("message", "") << "\n";
  DirectPddl out{std::move(im.action_model), std::move(im.state_plan), {}};
  for (const auto& a : im.actions)
    out.actions.push_back({a["command"], a["automaton"], a["pddl"], a["durative"]});
  return out;
}

// --server: POST /solve with the domain's name (or the file as action_model) and the plan.
int RunRemoteSolve(const SolveCliOptions& o) {
  Diagnostics d;
  auto plan = ReadJsonFile(o.file, d);
  if (!plan) {
    PrintError(Error::FromDiagnostics(ErrorCode::kInvalidInput, "cannot read " + o.file, d));
    return 1;
  }
  Json body = {{"state_plan", *plan}};
  if (auto e = AddDomain(body, o.domain)) {
    PrintError(*e);
    return 2;
  }
  Json options = {{"time_limit_ms", o.time_limit_ms}};
  if (!o.objective.empty()) options["objective"] = o.objective;
  if (!o.controllability.empty()) options["controllability"] = o.controllability;
  if (o.risk_bound) options["risk_bound"] = *o.risk_bound;
  if (o.horizon) options["horizon"] = *o.horizon;
  else options["max_horizon"] = o.max_horizon;
  body["options"] = options;
  auto r = PostJson(o.server, "/solve", body, o.time_limit_ms);
  if (auto* e = std::get_if<Error>(&r)) {
    PrintError(*e);
    return e->code == ErrorCode::kInvalidInput ? 1 : 3;
  }
  std::cout << (o.compact ? WireText(std::get<Json>(r)) : PrettyText(std::get<Json>(r))) << "\n";
  return 0;
}

// Exit code 2 for arguments that do not fit together; nullopt when they do.
std::optional<int> BadArguments(const SolveCliOptions& o) {
  const bool direct = o.domain.empty();  // --pddl DOMAIN PROBLEM imported here
  if (direct && (o.pddl_files.size() != 2 || !o.file.empty())) {
    std::cerr << "error: give --domain and a state plan file, or --pddl DOMAIN PROBLEM alone\n";
    return 2;
  }
  if (!direct && o.file.empty()) {
    std::cerr << "error: the state plan file is missing\n";
    return 2;
  }
  if (direct && !o.server.empty()) {
    std::cerr << "error: --server takes --domain and a state plan file\n";
    return 2;
  }
  return std::nullopt;
}

// What is solved: the domain and state plan from local files, or imported from PDDL.
struct SolveInputs {
  std::optional<Domain> domain;
  Json state_plan;
  std::optional<DirectPddl> imported;
};

// --domain and the state plan file, with LocalFileLimits (256 MiB), not the 4 MiB of an HTTP
// body. 0, or the exit code after the error is printed.
int LoadLocalInputs(const SolveCliOptions& o, const std::string& config, SolveInputs& in) {
  Diagnostics dd;
  in.domain = LoadDomainByNameOrPath(o.domain, config, dd, nullptr, LocalFileLimits());
  if (!in.domain) {
    PrintError(Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid domain", dd));
    return 2;
  }
  Diagnostics diags;
  auto json = ReadJsonFile(o.file, diags, LocalFileLimits());
  if (!json) {
    PrintError(Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid state plan " + o.file, diags));
    return 1;
  }
  in.state_plan = std::move(*json);
  return 0;
}

// --pddl DOMAIN PROBLEM alone: imported through the core. 0, or the exit code.
int ImportInputs(app::Core& core, const SolveCliOptions& o, SolveInputs& in) {
  in.imported = ImportForSolve(core, o);
  if (!in.imported) return 1;
  Diagnostics dd;
  in.domain = LoadDomain(in.imported->action_model, dd);
  if (!in.domain) {  // the import checks that its model loads: not expected
    PrintError(Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid imported domain", dd));
    return 2;
  }
  in.state_plan = in.imported->state_plan;
  return 0;
}

app::SolveCall MakeSolveCall(const SolveCliOptions& o, SolveInputs& in) {
  const bool direct = in.imported.has_value();
  app::SolveCall call;
  call.domain.loaded = std::make_shared<const Domain>(std::move(*in.domain));
  call.state_plan = std::move(in.state_plan);
  if (!o.objective.empty()) call.options.objective = o.objective;
  if (!o.controllability.empty()) call.options.controllability = o.controllability;
  call.options.risk_bound = o.risk_bound;
  call.options.time_limit_ms = o.time_limit_ms;
  if (o.horizon) call.options.horizon = *o.horizon;
  else call.options.max_horizon = direct && !o.max_horizon_given ? kMaxHorizonLimit : o.max_horizon;
  call.tune = [&o](SolveOptions& so) {
    so.threads = o.threads;
    so.search = o.search;
    so.portfolio = o.portfolio;
    so.decompose = !o.no_decompose;
    so.reuse_identical_parts = !o.no_reuse;
    so.redundant = !o.no_redundant;
    so.first_plan_ms = o.first_plan_ms;
    so.zone_proof_ms = o.zone_proof_ms;
    so.model_out = o.model_out;
  };
  return call;
}

// Prints the answer and writes --pddl-plan. 0, or 3 when the plan file cannot be written.
int WriteAnswer(const SolveCliOptions& o, const Json& answer, const std::optional<DirectPddl>& imported) {
  std::cout << (o.compact ? WireText(answer) : PrettyText(answer)) << "\n";
  if (o.pddl_plan.empty()) return 0;
  if (!imported) return WritePddlPlan(o, answer) ? 0 : 3;
  std::ofstream out(o.pddl_plan);
  out << pddl::PddlPlan(answer, imported->actions);
  if (!out) {
    std::cerr << "error: cannot write " << o.pddl_plan << "\n";
    return 3;
  }
  return 0;
}

int RunSolve(const SolveCliOptions& o) {
  if (auto bad = BadArguments(o)) return *bad;
  if (!o.server.empty()) return RunRemoteSolve(o);
  const bool direct = o.domain.empty();
  const std::string config = o.config_dir.empty() ? DefaultConfigDir() : o.config_dir;
  SolveInputs in;
  if (!direct)
    if (int rc = LoadLocalInputs(o, config, in)) return rc;
  if (!o.objective.empty() && !ParseObjective(o.objective)) {
    std::cerr << "error: unknown objective '" << o.objective << "'\n";
    return 1;
  }
  auto opened = OpenLocalCore(config, false);
  if (auto* e = std::get_if<Error>(&opened)) {
    PrintError(*e);
    return 3;
  }
  auto& core = *std::get<std::unique_ptr<app::Core>>(opened);
  if (direct)
    if (int rc = ImportInputs(core, o, in)) return rc;
  app::SolveCall call = MakeSolveCall(o, in);
  PrintStatePlanWarnings(core, call.domain, call.state_plan);
  auto result = core.Solve(call, {});
  if (auto* e = std::get_if<Error>(&result)) {
    PrintError(RelativeTo(*e, "/state_plan"));
    return e->code == ErrorCode::kInvalidInput ? 1 : 3;
  }
  return WriteAnswer(o, std::get<app::Answer>(result).document, in.imported);
}
}  // namespace

Runner AddSolve(CLI::App& app) {
  auto o = std::make_shared<SolveCliOptions>();
  CLI::App* sub = app.add_subcommand("solve", "Solve a state plan and print the trajectory JSON");
  sub->add_option("--domain", o->domain,
                  "Domain name or path (required unless --pddl gives a domain and a problem)");
  sub->add_option("file", o->file, "State plan JSON file (with --domain)");
  sub->add_option("--objective", o->objective, "cost, makespan or cost_then_makespan");
  sub->add_option("--controllability", o->controllability,
                  "contingent transitions: dynamic (default where there are any), strong or none")
      ->check(CLI::IsMember({"dynamic", "strong", "none"}));
  sub->add_option("--risk-bound", o->risk_bound,
                  "accept a plan that is not controllable when it fails at most this often")
      ->check(CLI::Range(0.0, 1.0));
  sub->add_option("--time-limit-ms", o->time_limit_ms, "Time limit for the whole solve")
      ->check(CLI::Range(1L, 3600L * 1000));
  auto* h = sub->add_option("--horizon", o->horizon, "Fixed number of events")
                ->check(CLI::Range(0, kMaxHorizonLimit));
  sub->add_option("--max-horizon", o->max_horizon,
                  "Most events tried (default 32; 200 with --pddl DOMAIN PROBLEM alone)")
      ->check(CLI::Range(0, kMaxHorizonLimit))
      ->excludes(h);
  sub->add_option("--threads", o->threads, "Gecode threads")->check(CLI::Range(1, 64));
  sub->add_option("--search", o->search,
                  "portfolio (default), g_first, tc_first, first_fail, transitions_first, default, "
                  "z3 (the z3 engine alone)");
  sub->add_option("--portfolio", o->portfolio, "Members run at once in portfolio mode: 1 g_first, 2 + tc_first, "
                  "3 + z3");
  sub->add_flag("--compact", o->compact, "Print the answer on one line, the bytes HTTP answers");
  sub->add_flag("--no-decompose", o->no_decompose, "Solve as one model even when it splits");
  sub->add_flag("--no-reuse", o->no_reuse, "Solve identical parts again (benchmarks)");
  sub->add_flag("--no-redundant", o->no_redundant, "Leave out redundant constraints (benchmarks)");
  sub->add_option("--first-plan-ms", o->first_plan_ms,
                  "Budget of the first-plan engine, and again of the neighbourhood search on "
                  "its plan (-1 automatic, 0 off)")
      ->check(CLI::Range(-1L, 3600L * 1000));
  sub->add_option("--zone-proof-ms", o->zone_proof_ms,
                  "Makespan: budget of the zone search that tries to prove the first plan "
                  "optimal or raise the bound (-1 automatic, 0 off)")
      ->check(CLI::Range(-1L, 3600L * 1000));
  sub->add_option("--model-out", o->model_out, "Write the (last) MiniZinc model here");
  auto* pddl = sub->add_option("--pddl", o->pddl_files,
                               "The PDDL domain and problem the model was imported from; "
                               "without --domain, imported and solved directly")
                   ->expected(1, 2)
                   ->check(CLI::ExistingFile);
  sub->add_option("--pddl-plan", o->pddl_plan,
                  "Write the trajectory as a PDDL 2.1 plan (time: (action args) [duration])")
      ->needs(pddl);
  sub->add_option("--config-dir", o->config_dir, "Configuration directory");
  sub->add_option("--server", o->server, "Solve on a running ctburton server, e.g. http://127.0.0.1:8080");
  return [o, sub]() {
    if (!sub->parsed()) return -1;
    o->max_horizon_given = sub->count("--max-horizon") > 0;
    return RunSolve(*o);
  };
}

}  // namespace ctb::cli
