#include "client/local_core.h"

#include <iostream>
#include <limits>

#include "planner/model/catalog.h"
#include "planner/solve/solve.h"
#include "translator/pipeline.h"

namespace ctb::cli {

std::variant<std::unique_ptr<app::Core>, Error> OpenLocalCore(const std::string& config_dir,
                                                               bool with_llm, int max_repairs) {
  app::CoreConfig c;
  c.config_dir = config_dir.empty() ? DefaultConfigDir() : config_dir;
  c.prompts_dir = DefaultPromptsDir();
  c.session_store = "memory";
  c.solver_workers = 1;
  c.solver_queue = 0;
  c.solver_memory_mb = 0;  // a local run is limited by the user's own machine
  c.probe_solver = false;
  c.default_time_limit_ms = 60000;
  c.max_time_limit_ms = 3600 * 1000;
  c.max_horizon_limit = kMaxHorizonLimit;
  const long big = std::numeric_limits<long>::max() / 4;
  c.budget = {big, big, big, big, big, big, big, big};
  if (with_llm) {
    auto llm = LlmConfig::FromEnv();
    if (auto* e = std::get_if<Error>(&llm)) return *e;
    c.llm = std::get<LlmConfig>(llm);
    if (max_repairs >= 0) c.llm.max_repairs = max_repairs;
  }
  return app::Core::Open(c);
}

Diagnostic RelativeTo(Diagnostic d, const std::string& prefix) {
  if (d.pointer.rfind(prefix, 0) == 0) d.pointer = d.pointer.substr(prefix.size());
  return d;
}

Error RelativeTo(Error e, const std::string& prefix) {
  for (auto& d : e.details) d = RelativeTo(std::move(d), prefix);
  return e;
}

void PrintStatePlanWarnings(app::Core& core, const app::DomainRef& domain, const Json& state_plan) {
  app::SolveCall call;
  call.domain = domain;
  call.state_plan = state_plan;
  auto v = core.Validate(call);
  if (auto* ok = std::get_if<app::ValidateAnswer>(&v))
    for (const auto& w : ok->warnings) std::cerr << "warning: " << RelativeTo(w, "/state_plan").ToString() << "\n";
}

std::variant<LocalProblem, Error> OpenLocalProblem(const std::string& domain, const std::string& config_dir,
                                                   const std::string& file) {
  const std::string config = config_dir.empty() ? DefaultConfigDir() : config_dir;
  Diagnostics d;
  auto loaded = LoadDomainByNameOrPath(domain, config, d, nullptr, LocalFileLimits());
  if (!loaded) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid domain", d);
  auto state_plan = ReadJsonFile(file, d, LocalFileLimits());
  if (!state_plan) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid state plan " + file, d);
  auto opened = OpenLocalCore(config, /*with_llm=*/false);
  if (auto* e = std::get_if<Error>(&opened)) return *e;
  LocalProblem p{std::move(std::get<std::unique_ptr<app::Core>>(opened)), {}, std::move(*state_plan)};
  p.domain.loaded = std::make_shared<const Domain>(std::move(*loaded));
  PrintStatePlanWarnings(*p.core, p.domain, p.state_plan);
  return p;
}

}  // namespace ctb::cli
