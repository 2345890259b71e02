#include <iostream>
#include <memory>
#include <string>

#include "client/commands.h"
#include "planner/model/catalog.h"
#include "translator/pipeline.h"

namespace ctb::cli {

namespace {
struct TranslateCliOptions {
  std::string domain, command, prompting = "cot", config_dir;
};

int ExitCode(ErrorCode c) { return ExitCodeFor(c); }

int RunTranslate(const TranslateCliOptions& o) {
  auto fail = [](const Error& e) {
    PrintError(e);
    return ExitCode(e.code);
  };
  Diagnostics dd;
  auto domain = LoadDomainByNameOrPath(o.domain, o.config_dir.empty() ? DefaultConfigDir() : o.config_dir, dd);
  if (!domain) return fail(Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid domain", dd));
  auto prompting = ParsePrompting(o.prompting);
  if (!prompting) return fail({ErrorCode::kInvalidInput, "--prompting must be cot or direct", {}});
  auto cfg = LlmConfig::FromEnv();
  if (auto* e = std::get_if<Error>(&cfg)) return fail(*e);
  auto client = MakeClient(std::get<LlmConfig>(cfg));
  if (auto* e = std::get_if<Error>(&client)) return fail(*e);
  TranslateOptions to;
  to.prompting = *prompting;
  to.max_repairs = std::get<LlmConfig>(cfg).max_repairs;
  to.response_format = std::get<LlmConfig>(cfg).response_format;
  auto r = Translate(*domain, o.command, *std::get<std::unique_ptr<LlmClient>>(client), to);
  if (auto* e = std::get_if<Error>(&r)) return fail(*e);
  const auto& t = std::get<TranslateResult>(r);
  for (const auto& w : t.warnings) std::cerr << "warning: " << w.ToString() << "\n";
  Json out = {{"state_plan", t.state_plan}, {"reasoning", t.reasoning},
              {"llm_calls", t.llm_calls}, {"repairs", t.repairs}};
  if (!t.warnings.empty()) out["warnings"] = WarningsJson(t.warnings);
  std::cout << out.dump(2, ' ', false, Json::error_handler_t::replace) << "\n";
  return 0;
}
}  // namespace

Runner AddTranslate(CLI::App& app) {
  auto o = std::make_shared<TranslateCliOptions>();
  CLI::App* sub = app.add_subcommand("translate", "Turn a command in natural language into a state plan");
  sub->add_option("--domain", o->domain, "Domain name or path")->required();
  sub->add_option("command", o->command, "What the team should do")->required();
  sub->add_option("--prompting", o->prompting, "cot (default) or direct");
  sub->add_option("--config-dir", o->config_dir, "Configuration directory");
  return [o, sub]() { return sub->parsed() ? RunTranslate(*o) : -1; };
}

}  // namespace ctb::cli
