#include <iostream>
#include <memory>
#include <string>

#include "client/commands.h"
#include "client/remote.h"
#include "client/local_core.h"
#include "planner/model/catalog.h"

namespace ctb::cli {

namespace {
struct PlanCliOptions {
  std::string server, domain, command, session, prompting = "cot", objective, config_dir;
  long time_limit_ms = 60000;
};

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
    std::cout << PrettyText(std::get<Json>(r)) << "\n";
    return 0;
  }
  if (!o.session.empty()) return Fail({ErrorCode::kInvalidInput, "--session needs --server (sessions live in the server)", {}});
  auto opened = OpenLocalCore(o.config_dir, true);
  if (auto* e = std::get_if<Error>(&opened)) return Fail(*e);
  auto& core = *std::get<std::unique_ptr<app::Core>>(opened);
  app::PlanCall call;
  call.domain = o.domain;
  call.command = o.command;
  call.prompting = o.prompting;
  call.options.time_limit_ms = o.time_limit_ms;
  if (!o.objective.empty()) call.options.objective = o.objective;
  auto r = core.Plan(call, {});
  if (auto* e = std::get_if<Error>(&r)) return Fail(*e);
  const auto& p = std::get<app::PlanAnswer>(r);
  Json out = {{"state_plan", p.translation.state_plan}, {"reasoning", p.translation.reasoning},
              {"trajectory", p.answer.document}};
  if (!p.translation.warnings.empty()) out["warnings"] = p.translation.warnings;
  std::cout << PrettyText(out) << "\n";
  return 0;
}
}  // namespace

Runner AddPlan(CLI::App& app) {
  auto o = std::make_shared<PlanCliOptions>();
  CLI::App* sub = app.add_subcommand("plan", "Natural language to a verified plan (locally or via --server)");
  sub->add_option("--server", o->server, "A running ctburton server, e.g. http://127.0.0.1:8080");
  sub->add_option("--domain", o->domain, "Domain name (shipped, or stored on the server)")->required();
  sub->add_option("command", o->command, "What the team should do")->required();
  sub->add_option("--session", o->session, "Continue a dialogue (server mode)");
  sub->add_option("--prompting", o->prompting, "cot (default) or direct");
  sub->add_option("--objective", o->objective, "cost, makespan or cost_then_makespan");
  sub->add_option("--time-limit-ms", o->time_limit_ms, "Solver time limit")->check(CLI::Range(1L, 3600000L));
  sub->add_option("--config-dir", o->config_dir, "Configuration directory (local mode)");
  return [o, sub]() { return sub->parsed() ? RunPlan(*o) : -1; };
}

}  // namespace ctb::cli
