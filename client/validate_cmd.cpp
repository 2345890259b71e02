#include <iostream>
#include <memory>
#include <string>

#include "client/commands.h"
#include "planner/model/catalog.h"
#include "planner/model/state_plan.h"

namespace ctb::cli {

namespace {
struct ValidateOptions {
  std::string domain;
  std::string file;
  std::string config_dir;
};

int RunValidate(const ValidateOptions& o) {
  std::string config = o.config_dir.empty() ? DefaultConfigDir() : o.config_dir;
  Diagnostics dd;
  auto domain = LoadDomainByNameOrPath(o.domain, config, dd);
  if (!domain) {
    std::cout << "invalid domain\n";
    for (const auto& e : dd.errors()) std::cout << e.ToString() << "\n";
    return 2;
  }
  Diagnostics diags;
  auto json = ReadJsonFile(o.file, diags);
  if (json) LoadStatePlan(*json, *domain, diags);
  if (!diags.ok()) {
    std::cout << "invalid: " << o.file << "\n";
    for (const auto& e : diags.errors()) std::cout << e.ToString() << "\n";
    return 1;
  }
  std::cout << "valid\n";
  for (const auto& w : diags.warnings()) std::cout << "warning: " << w.ToString() << "\n";
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
