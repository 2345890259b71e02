// `ctburton schema --domain NAME|PATH`: the JSON Schema of the domain's state plans, as sent to
// the LLM endpoint with CTB_LLM_RESPONSE_FORMAT=json_schema.
#include <iostream>
#include <memory>
#include <string>

#include "client/commands.h"
#include "planner/model/catalog.h"
#include "translator/schema.h"

namespace ctb::cli {

namespace {
struct SchemaOptions {
  std::string domain, config_dir;
};

int RunSchema(const SchemaOptions& o) {
  Diagnostics dd;
  auto domain = LoadDomainByNameOrPath(
      o.domain, o.config_dir.empty() ? DefaultConfigDir() : o.config_dir, dd);
  if (!domain) {
    PrintError(Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid domain", dd));
    return 2;
  }
  std::cout << PrettyText(StatePlanSchema(*domain)) << "\n";
  return 0;
}
}  // namespace

Runner AddSchema(CLI::App& app) {
  auto o = std::make_shared<SchemaOptions>();
  CLI::App* sub = app.add_subcommand("schema", "Print the JSON Schema of a domain's state plans");
  sub->add_option("--domain", o->domain, "Domain name or path")->required();
  sub->add_option("--config-dir", o->config_dir, "Configuration directory");
  return [o, sub]() { return sub->parsed() ? RunSchema(*o) : -1; };
}

}  // namespace ctb::cli
