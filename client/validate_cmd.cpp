// `ctburton validate`: a state plan file checked against a domain by the application core (the
// check POST /validate makes), one located error or warning a line.
#include <iostream>
#include <memory>
#include <string>

#include "client/commands.h"
#include "client/local_core.h"
#include "planner/model/catalog.h"

namespace ctb::cli {

namespace {
struct ValidateOptions {
  std::string domain;
  std::string file;
  std::string config_dir;
};

int Invalid(const std::string& file, const std::vector<Diagnostic>& errors) {
  std::cout << "invalid: " << file << "\n";
  for (const auto& e : errors) std::cout << e.ToString() << "\n";
  return 1;
}

int RunValidate(const ValidateOptions& o) {
  const std::string config = o.config_dir.empty() ? DefaultConfigDir() : o.config_dir;
  Diagnostics dd;
  auto domain = LoadDomainByNameOrPath(o.domain, config, dd, nullptr, LocalFileLimits());
  if (!domain) {
    std::cout << "invalid domain\n";
    for (const auto& e : dd.errors()) std::cout << e.ToString() << "\n";
    return 2;
  }
  Diagnostics diags;
  auto json = ReadJsonFile(o.file, diags, LocalFileLimits());
  if (!json) return Invalid(o.file, diags.errors());
  auto opened = OpenLocalCore(config, /*with_llm=*/false);
  if (auto* e = std::get_if<Error>(&opened)) return Fail(*e);
  app::SolveCall call;
  call.domain.loaded = std::make_shared<const Domain>(std::move(*domain));
  call.state_plan = std::move(*json);
  auto r = std::get<std::unique_ptr<app::Core>>(opened)->Validate(call);
  if (auto* e = std::get_if<Error>(&r)) {
    if (e->code != ErrorCode::kInvalidInput) return Fail(*e);
    return Invalid(o.file, RelativeTo(*e, "/state_plan").details);
  }
  std::cout << "valid\n";
  for (const auto& w : std::get<app::ValidateAnswer>(r).warnings)
    std::cout << "warning: " << RelativeTo(w, "/state_plan").ToString() << "\n";
  return 0;
}
}  // namespace

Runner AddValidate(CLI::App& app) {
  auto opts = std::make_shared<ValidateOptions>();
  CLI::App* sub = app.add_subcommand("validate", "Check a state plan against a domain");
  sub->add_option("--domain", opts->domain, "Domain name (config/domains/NAME.json) or path")
      ->required();
  sub->add_option("--config-dir", opts->config_dir, "Configuration directory");
  sub->add_option("file", opts->file, "State plan JSON file")->required();
  return [opts, sub]() { return sub->parsed() ? RunValidate(*opts) : -1; };
}

}  // namespace ctb::cli
