// `ctburton eval --suite FILE [--json] [--time-limit-ms N] [--prompting cot|direct]` (contract
// section 15): how well the configured LLM (or, offline, the recordings of CTB_LLM_REPLAY)
// translates a suite of commands with reference state plans.
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "client/commands.h"
#include "client/local_core.h"
#include "planner/model/json_io.h"

namespace ctb::cli {

namespace {

struct EvalCliOptions {
  std::string suite, prompting, config_dir;
  long time_limit_ms = 0;
  bool json = false;
};

// "7 (88 %)": a count and its share of n.
std::string Rate(int count, int n) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%d (%.0f %%)", count, n ? 100.0 * count / n : 0.0);
  return buf;
}

int RunEval(const EvalCliOptions& o) {
  Diagnostics diags;
  auto suite = ReadJsonFile(o.suite, diags);
  if (!suite) return Fail(Error::FromDiagnostics(ErrorCode::kInvalidInput, "cannot read the suite " + o.suite, diags));
  auto opened = OpenLocalCore(o.config_dir, true);
  if (auto* e = std::get_if<Error>(&opened)) return Fail(*e);
  auto& core = *std::get<std::unique_ptr<app::Core>>(opened);
  app::EvalCall call;
  call.suite = *suite;
  if (!o.prompting.empty()) call.prompting = o.prompting;
  if (o.time_limit_ms > 0) call.time_limit_ms = o.time_limit_ms;
  int parsed = 0, valid = 0, solvable = 0;
  auto each = [&](const Json& line) {
    parsed += line["parsed"].get<bool>();
    valid += line["valid"].get<bool>();
    solvable += line["solvable"].get<bool>();
    if (o.json) {
      std::cout << WireText(line) << std::endl;
      return;
    }
    std::cout << "item " << line["item"] << " (" << line["domain"].get<std::string>() << "): "
              << line["verdict"].get<std::string>() << ", " << line["ms"] << " ms";
    if (line.contains("why")) std::cout << " - " << line["why"].get<std::string>();
    std::cout << std::endl;
  };
  auto r = core.Eval(call, {}, each);
  if (auto* e = std::get_if<Error>(&r)) return Fail(*e);
  const Json& t = std::get<Json>(r);
  if (o.json) {
    std::cout << t.dump() << std::endl;
    return 0;
  }
  const int n = t["items"].get<int>();
  auto rate = [&](const char* key) { return Rate(t[key].get<int>(), n); };
  std::cout << "items " << n << ": parsed " << Rate(parsed, n) << ", valid " << Rate(valid, n)
            << ", solvable " << Rate(solvable, n) << ", equivalent " << rate("equivalent")
            << ", not equivalent " << rate("not_equivalent") << ", unparsed " << rate("unparsed")
            << ", invalid " << rate("invalid") << ", unknown " << rate("unknown") << std::endl;
  return 0;
}

}  // namespace

Runner AddEval(CLI::App& app) {
  auto o = std::make_shared<EvalCliOptions>();
  CLI::App* sub = app.add_subcommand(
      "eval", "Measure how well the configured LLM translates a suite of commands (CTB_LLM_* or CTB_LLM_REPLAY)");
  sub->add_option("--suite", o->suite, "A JSON list of {domain, command, reference}")->required();
  sub->add_flag("--json", o->json, "One JSON object a line per item, then the totals");
  sub->add_option("--time-limit-ms", o->time_limit_ms, "Time limit of each solve (default 10000)")
      ->check(CLI::Range(1L, 3600000L));
  sub->add_option("--prompting", o->prompting, "cot (default) or direct");
  sub->add_option("--config-dir", o->config_dir, "Configuration directory");
  return [o, sub]() { return sub->parsed() ? RunEval(*o) : -1; };
}

}  // namespace ctb::cli
