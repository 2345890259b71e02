#include <iostream>
#include <memory>
#include <string>

#include "client/commands.h"
#include "client/remote.h"
#include "planner/explain/explain.h"
#include "planner/model/catalog.h"
#include "planner/solve/solve.h"
#include "translator/pipeline.h"

namespace ctb::cli {

namespace {
struct PlanCliOptions {
  std::string server, domain, command, session, prompting = "cot", objective, config_dir;
  long time_limit_ms = 60000;
};

int Fail(const Error& e) {
  PrintError(e);
  return ExitCodeFor(e.code);
}

int RunPlan(const PlanCliOptions& o) {
  if (!o.objective.empty() && !ParseObjective(o.objective))
    return Fail({ErrorCode::kInvalidInput, "--objective must be cost, makespan or cost_then_makespan", {}});
  Json options = {{"time_limit_ms", o.time_limit_ms}};
  if (!o.objective.empty()) options["objective"] = o.objective;
  if (!o.server.empty()) {
    Json body = {{"domain", o.domain}, {"command", o.command}, {"prompting", o.prompting}, {"options", options}};
    if (!o.session.empty()) body["session"] = o.session;
    auto r = PostJson(o.server, "/plan", body, o.time_limit_ms);
    if (auto* e = std::get_if<Error>(&r)) return Fail(*e);
    std::cout << std::get<Json>(r).dump(2) << "\n";
    return 0;
  }
  if (!o.session.empty()) return Fail({ErrorCode::kInvalidInput, "--session needs --server (sessions live in the server)", {}});
  Diagnostics dd;
  auto domain = LoadDomainByNameOrPath(o.domain, o.config_dir.empty() ? DefaultConfigDir() : o.config_dir, dd);
  if (!domain) return Fail(Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid domain", dd));
  auto cfg = LlmConfig::FromEnv();
  if (auto* e = std::get_if<Error>(&cfg)) return Fail(*e);
  auto client = MakeClient(std::get<LlmConfig>(cfg));
  if (auto* e = std::get_if<Error>(&client)) return Fail(*e);
  TranslateOptions to;
  auto p = ParsePrompting(o.prompting);
  if (!p) return Fail({ErrorCode::kInvalidInput, "--prompting must be cot or direct", {}});
  to.prompting = *p;
  to.max_repairs = std::get<LlmConfig>(cfg).max_repairs;
  to.response_format = std::get<LlmConfig>(cfg).response_format;
  auto t = Translate(*domain, o.command, *std::get<std::unique_ptr<LlmClient>>(client), to);
  if (auto* e = std::get_if<Error>(&t)) return Fail(*e);
  const auto& tr = std::get<TranslateResult>(t);
  Diagnostics d;
  auto sp = LoadStatePlan(tr.state_plan, *domain, d);
  if (!sp) return Fail(Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid state plan", d));
  SolveOptions so;
  so.time_limit_ms = o.time_limit_ms;
  if (!o.objective.empty()) so.objective = ParseObjective(o.objective);
  auto s = Solve(*domain, *sp, so);
  if (auto* e = std::get_if<Error>(&s)) return Fail(*e);
  AnnotateAnswer(*domain, *sp, so, std::get<Json>(s));
  Json out = {{"state_plan", tr.state_plan}, {"reasoning", tr.reasoning}, {"trajectory", std::get<Json>(s)}};
  if (!tr.warnings.empty()) out["warnings"] = WarningsJson(tr.warnings);
  std::cout << out.dump(2, ' ', false, Json::error_handler_t::replace) << "\n";
  return 0;
}
}  // namespace

Runner AddPlan(CLI::App& app) {
  auto o = std::make_shared<PlanCliOptions>();
  CLI::App* sub = app.add_subcommand("plan", "Natural language to a verified plan (locally or via --server)");
  sub->add_option("--server", o->server, "A running ctburton server, e.g. http://127.0.0.1:8080");
  sub->add_option("--domain", o->domain, "Domain name")->required();
  sub->add_option("command", o->command, "What the team should do")->required();
  sub->add_option("--session", o->session, "Continue a dialogue (server mode)");
  sub->add_option("--prompting", o->prompting, "cot (default) or direct");
  sub->add_option("--objective", o->objective, "cost, makespan or cost_then_makespan");
  sub->add_option("--time-limit-ms", o->time_limit_ms, "Solver time limit")->check(CLI::Range(1L, 3600000L));
  sub->add_option("--config-dir", o->config_dir, "Configuration directory (local mode)");
  return [o, sub]() { return sub->parsed() ? RunPlan(*o) : -1; };
}

}  // namespace ctb::cli
