// `ctburton replan`: one replan from files (contract section 11), the answer JSON on stdout.
#include <iostream>
#include <memory>
#include <string>

#include "client/commands.h"
#include "client/replan_common.h"
#include "planner/model/catalog.h"
#include "planner/replan/replan.h"

namespace ctb::cli {

namespace {

struct ReplanCliOptions {
  std::string domain, file, config_dir, objective, keep;
  std::string trajectory, request, executed, observed, blocked;
  std::optional<double> now;
  long time_limit_ms = 60000;
  int max_horizon = 32;
};

// A flag that holds JSON text, or @FILE.
std::optional<Json> JsonArg(const std::string& arg, const std::string& flag, Diagnostics& d) {
  if (!arg.empty() && arg[0] == '@') return ReadJsonFile(arg.substr(1), d);
  auto j = ParseJsonStrict(arg, d);
  if (!j) d.Error(flag, "not JSON (give the JSON itself or @FILE)");
  return j;
}

int RunReplan(const ReplanCliOptions& o) {
  auto loaded = LoadProblem(o.domain, o.config_dir, o.file);
  if (auto* e = std::get_if<Error>(&loaded)) {
    PrintError(*e);
    return 1;
  }
  auto& [domain, sp] = std::get<LoadedProblem>(loaded);
  Diagnostics d;
  Json body = Json::object();
  if (!o.request.empty()) {
    auto r = ReadJsonFile(o.request, d);
    if (r) body = *r;
  }
  if (!o.trajectory.empty()) {
    auto t = ReadJsonFile(o.trajectory, d);
    if (t) body["trajectory"] = t->contains("trajectory") ? (*t)["trajectory"] : *t;
  }
  if (o.now) body["now"] = *o.now;
  for (auto [arg, key] : {std::pair{&o.executed, "executed"}, std::pair{&o.observed, "observed"},
                          std::pair{&o.blocked, "blocked"}})
    if (!arg->empty())
      if (auto j = JsonArg(*arg, std::string("--") + key, d)) body[key] = *j;
  if (!d.ok()) {
    PrintError(Error::FromDiagnostics(ErrorCode::kInvalidInput, "cannot read the request", d));
    return 1;
  }
  if (!o.keep.empty()) body["options"]["keep"] = o.keep;
  ReplanRequest req;
  ReplanOptions ro;
  if (auto e = ReadReplanRequest(body, req, &ro.keep)) {
    PrintError(*e);
    return 1;
  }
  if (!o.objective.empty()) {
    ro.solve.objective = ParseObjective(o.objective);
    if (!ro.solve.objective) {
      std::cerr << "error: unknown objective '" << o.objective << "'\n";
      return 1;
    }
  }
  ro.solve.time_limit_ms = o.time_limit_ms;
  ro.solve.max_horizon = o.max_horizon;
  auto r = Replan(domain, sp, req, ro);
  if (auto* e = std::get_if<Error>(&r)) {
    PrintError(*e);
    return ExitCodeFor(e->code);
  }
  std::cout << std::get<Json>(r).dump(2) << "\n";
  return 0;
}

}  // namespace

Runner AddReplan(CLI::App& app) {
  auto o = std::make_shared<ReplanCliOptions>();
  CLI::App* sub = app.add_subcommand(
      "replan", "Replan from what happened up to now (contract section 11); JSON on stdout");
  sub->add_option("--domain", o->domain, "Domain name or path")->required();
  sub->add_option("file", o->file, "State plan JSON file")->required();
  sub->add_option("--trajectory", o->trajectory, "The plan being executed (a trajectory JSON)");
  sub->add_option("--now", o->now, "Seconds since the plan started");
  sub->add_option("--executed", o->executed, "What happened, as JSON or @FILE (the whole history)");
  sub->add_option("--observed", o->observed, "Where automata are, as JSON or @FILE");
  sub->add_option("--blocked", o->blocked, "Transitions that cannot be made, as JSON or @FILE");
  sub->add_option("--request", o->request, "A request body (now, executed, observed, blocked, "
                  "trajectory, options); the flags above override it");
  sub->add_option("--keep", o->keep, "none (default), started or min_change");
  sub->add_option("--objective", o->objective, "cost, makespan or cost_then_makespan");
  sub->add_option("--time-limit-ms", o->time_limit_ms, "Time limit")->check(CLI::Range(1L, 3600L * 1000));
  sub->add_option("--max-horizon", o->max_horizon, "Most events of the future (default 32)")
      ->check(CLI::Range(0, kMaxHorizonLimit));
  sub->add_option("--config-dir", o->config_dir, "Configuration directory");
  return [o, sub]() { return sub->parsed() ? RunReplan(*o) : -1; };
}

}  // namespace ctb::cli
