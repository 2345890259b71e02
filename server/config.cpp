#include "server/config.h"

#include <cstdlib>
#include <filesystem>

#include "planner/model/catalog.h"
#include "translator/pipeline.h"

#ifndef CTB_BUILTIN_STATIC_DIR
#define CTB_BUILTIN_STATIC_DIR "server/static"
#endif
#ifndef CTB_BUILTIN_RECORDINGS_DIR
#define CTB_BUILTIN_RECORDINGS_DIR "tests/recordings/thesis"
#endif

namespace ctb::server {

std::variant<ServerConfig, Error> ServerConfig::Load(const std::string& file) {
  ServerConfig c;
  c.config_dir = DefaultConfigDir();
  c.prompts_dir = DefaultPromptsDir();
  c.static_dir = std::filesystem::is_directory("server/static") ? "server/static" : CTB_BUILTIN_STATIC_DIR;
  c.recordings_dir = std::filesystem::is_directory("tests/recordings/thesis") ? "tests/recordings/thesis"
                                                                             : CTB_BUILTIN_RECORDINGS_DIR;
  Diagnostics d;
  if (!file.empty()) {
    auto j = ReadJsonFile(file, d);
    if (!j) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "cannot read config " + file, d);
    ObjectReader r(*j, "", d);
    r.CheckKeys({"host", "port", "config_dir", "prompts_dir", "static_dir", "minizinc", "recordings_dir",
                 "max_body_bytes", "read_timeout_s", "write_timeout_s", "solver_workers",
                 "solver_queue", "default_time_limit_ms", "max_time_limit_ms", "max_horizon_limit",
                 "max_sessions", "session_idle_s", "shutdown_grace_ms"});
    auto str = [&](const char* k, std::string& out) {
      if (auto v = r.String(k, false)) out = *v;
    };
    auto num = [&](const char* k, auto& out) {
      if (auto v = r.NonNegative(k, false)) out = static_cast<std::remove_reference_t<decltype(out)>>(*v);
    };
    str("host", c.host);
    num("port", c.port);
    str("config_dir", c.config_dir);
    str("prompts_dir", c.prompts_dir);
    str("static_dir", c.static_dir);
    str("minizinc", c.minizinc);
    str("recordings_dir", c.recordings_dir);
    num("max_body_bytes", c.max_body_bytes);
    num("read_timeout_s", c.read_timeout_s);
    num("write_timeout_s", c.write_timeout_s);
    num("solver_workers", c.solver_workers);
    num("solver_queue", c.solver_queue);
    num("default_time_limit_ms", c.default_time_limit_ms);
    num("max_time_limit_ms", c.max_time_limit_ms);
    num("max_horizon_limit", c.max_horizon_limit);
    num("max_sessions", c.max_sessions);
    num("session_idle_s", c.session_idle_s);
    num("shutdown_grace_ms", c.shutdown_grace_ms);
    if (!d.ok()) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid config " + file, d);
  }
  if (const char* p = std::getenv("CTB_PORT"); p && *p) c.port = std::atoi(p);
  if (const char* h = std::getenv("CTB_HOST"); h && *h) c.host = h;
  auto llm = LlmConfig::FromEnv();
  if (auto* e = std::get_if<Error>(&llm)) return *e;
  c.llm = std::get<LlmConfig>(llm);
  return c;
}

std::optional<Error> ServerConfig::Validate() const {
  Diagnostics d;
  if (port < 0 || port > 65535) d.Error("/port", "port must be 0..65535");
  if (max_body_bytes < 1024 || max_body_bytes > (64L << 20)) d.Error("/max_body_bytes", "must be 1 KiB..64 MiB");
  if (solver_workers < 1 || solver_workers > 64) d.Error("/solver_workers", "must be 1..64");
  if (solver_queue < 0 || solver_queue > 1024) d.Error("/solver_queue", "must be 0..1024");
  if (max_time_limit_ms < 100 || max_time_limit_ms > 3600000) d.Error("/max_time_limit_ms", "must be 100..3600000");
  if (default_time_limit_ms < 100 || default_time_limit_ms > max_time_limit_ms)
    d.Error("/default_time_limit_ms", "must be 100..max_time_limit_ms");
  if (read_timeout_s < 1 || write_timeout_s < 1) d.Error("/read_timeout_s", "timeouts must be >= 1 s");
  if (max_sessions < 1) d.Error("/max_sessions", "must be >= 1");
  if (!std::filesystem::is_directory(config_dir + "/domains"))
    d.Error("/config_dir", "no domains/ folder in '" + config_dir + "'");
  if (d.ok()) return std::nullopt;
  return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid server configuration", d);
}

Json ServerConfig::ToLogJson() const {
  return {{"host", host}, {"port", port}, {"config_dir", config_dir}, {"static_dir", static_dir},
          {"max_body_bytes", max_body_bytes}, {"solver_workers", solver_workers},
          {"solver_queue", solver_queue}, {"default_time_limit_ms", default_time_limit_ms},
          {"max_time_limit_ms", max_time_limit_ms}, {"llm_base_url", llm.base_url},
          {"llm_model", llm.model}, {"llm_api_key", llm.MaskedKey()},
          {"llm_replay", llm.replay_dir.empty() ? recordings_dir + " (fallback)" : llm.replay_dir}};
}

}  // namespace ctb::server
