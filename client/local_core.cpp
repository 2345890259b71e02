#include "client/local_core.h"

#include <limits>

#include "planner/model/catalog.h"
#include "planner/solve/solve.h"
#include "translator/pipeline.h"

namespace ctb::cli {

std::variant<std::unique_ptr<app::Core>, Error> OpenLocalCore(const std::string& config_dir,
                                                               bool with_llm) {
  app::CoreConfig c;
  c.config_dir = config_dir.empty() ? DefaultConfigDir() : config_dir;
  c.prompts_dir = DefaultPromptsDir();
  c.session_store = "memory";
  c.solver_workers = 1;
  c.solver_queue = 0;
  c.solver_memory_mb = 0;  // a local run is limited by the user's own machine
  c.default_time_limit_ms = 60000;
  c.max_time_limit_ms = 3600 * 1000;
  c.max_horizon_limit = kMaxHorizonLimit;
  const long big = std::numeric_limits<long>::max() / 4;
  c.budget = {big, big, big, big, big, big, big, big};
  if (with_llm) {
    auto llm = LlmConfig::FromEnv();
    if (auto* e = std::get_if<Error>(&llm)) return *e;
    c.llm = std::get<LlmConfig>(llm);
  }
  return app::Core::Open(c);
}

Error RelativeTo(Error e, const std::string& prefix) {
  for (auto& d : e.details)
    if (d.pointer.rfind(prefix, 0) == 0) d.pointer = d.pointer.substr(prefix.size());
  return e;
}

}  // namespace ctb::cli
