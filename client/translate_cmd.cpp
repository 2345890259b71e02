// `ctburton translate`: a command in words to a state plan, through the application core (the
// same translation as POST /translate), with the LLM from the environment (CTB_LLM_*).
#include <iostream>
#include <memory>
#include <string>

#include "client/commands.h"
#include "client/local_core.h"
#include "planner/model/catalog.h"

namespace ctb::cli {

namespace {
struct TranslateCliOptions {
  std::string domain, command, prompting = "cot", config_dir;
};

int RunTranslate(const TranslateCliOptions& o) {
  const std::string config = o.config_dir.empty() ? DefaultConfigDir() : o.config_dir;
  Diagnostics dd;
  auto domain = LoadDomainByNameOrPath(o.domain, config, dd);
  if (!domain) return Fail(Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid domain", dd));
  auto opened = OpenLocalCore(config, /*with_llm=*/true);
  if (auto* e = std::get_if<Error>(&opened)) return Fail(*e);
  app::TranslateCall call;
  call.domain.loaded = std::make_shared<const Domain>(std::move(*domain));
  call.command = o.command;
  call.prompting = o.prompting;
  auto r = std::get<std::unique_ptr<app::Core>>(opened)->Translate(call, {});
  if (auto* e = std::get_if<Error>(&r)) return Fail(*e);
  const auto& t = std::get<app::TranslateAnswer>(r);
  for (const auto& w : t.warnings)
    std::cerr << "warning: " << w.value("path", "/") << ": " << w.value("message", "") << "\n";
  Json out = {{"state_plan", t.state_plan}, {"reasoning", t.reasoning},
              {"llm_calls", t.llm_calls}, {"repairs", t.repairs}};
  if (!t.warnings.empty()) out["warnings"] = t.warnings;
  std::cout << PrettyText(out) << "\n";
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
