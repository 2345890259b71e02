#include "server/config.h"

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <limits>

#include "mqtt/url.h"
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
                 "max_body_bytes", "max_network_body_bytes", "read_timeout_s", "write_timeout_s", "solver_workers",
                 "solver_queue", "default_time_limit_ms", "max_time_limit_ms", "max_horizon_limit",
                 "max_sessions", "session_idle_s", "execution_lease_ms", "shutdown_grace_ms", "body_timeout_s", "keep_alive_s",
                 "max_connections", "max_connections_per_address", "solver_memory_mb", "budget",
                 "data_dir", "session_store", "demo", "grpc_port", "grpc_host", "grpc_tls_cert",
                 "grpc_tls_key", "max_grpc_streams_per_client", "api_keys_file", "mqtt_url", "mqtt_client_id"});
    auto str = [&](const char* k, std::string& out) {
      if (auto v = r.String(k, false)) out = *v;
    };
    // A number must fit its field: no cast of an out-of-range value (Validate() then checks the
    // field's own range).
    auto num_in = [&](ObjectReader& rd, const char* k, auto& out) {
      using T = std::remove_reference_t<decltype(out)>;
      const Json* v = rd.Get(k);
      if (!v) return;
      if (!v->is_number_integer() || v->get<long long>() < 0 ||
          v->get<long long>() > static_cast<long long>(std::numeric_limits<T>::max())) {
        d.Error(rd.Child(k), "must be an integer between 0 and " + std::to_string(std::numeric_limits<T>::max()));
        return;
      }
      out = static_cast<T>(v->get<long long>());
    };
    auto num = [&](const char* k, auto& out) { num_in(r, k, out); };
    str("host", c.host);
    num("port", c.port);
    str("config_dir", c.config_dir);
    str("prompts_dir", c.prompts_dir);
    str("static_dir", c.static_dir);
    str("minizinc", c.minizinc);
    str("recordings_dir", c.recordings_dir);
    str("data_dir", c.data_dir);
    str("session_store", c.session_store);
    str("grpc_host", c.grpc_host);
    str("grpc_tls_cert", c.grpc_tls_cert);
    str("grpc_tls_key", c.grpc_tls_key);
    str("api_keys_file", c.api_keys_file);
    str("mqtt_url", c.mqtt_url);
    str("mqtt_client_id", c.mqtt_client_id);
    if (const Json* v = r.Get("grpc_port")) {
      if (v->is_number_integer() && v->get<long long>() >= -1 && v->get<long long>() <= 65535)
        c.grpc_port = v->get<int>();
      else
        d.Error("/grpc_port", "must be -1 (off) or a port number 0..65535");
    }
    num("max_grpc_streams_per_client", c.max_grpc_streams_per_client);
    if (const Json* v = r.Get("demo")) {
      if (v->is_boolean()) c.demo = v->get<bool>();
      else d.Error("/demo", "must be true or false");
    }
    num("max_body_bytes", c.max_body_bytes);
    num("max_network_body_bytes", c.max_network_body_bytes);
    num("read_timeout_s", c.read_timeout_s);
    num("write_timeout_s", c.write_timeout_s);
    num("solver_workers", c.solver_workers);
    num("solver_queue", c.solver_queue);
    num("default_time_limit_ms", c.default_time_limit_ms);
    num("max_time_limit_ms", c.max_time_limit_ms);
    num("max_horizon_limit", c.max_horizon_limit);
    num("max_sessions", c.max_sessions);
    num("session_idle_s", c.session_idle_s);
    num("execution_lease_ms", c.execution_lease_ms);
    num("shutdown_grace_ms", c.shutdown_grace_ms);
    num("body_timeout_s", c.body_timeout_s);
    num("keep_alive_s", c.keep_alive_s);
    num("max_connections", c.max_connections);
    num("max_connections_per_address", c.max_connections_per_address);
    num("solver_memory_mb", c.solver_memory_mb);
    if (r.Has("budget")) {
      ObjectReader b((*j)["budget"], "/budget", d);
      b.CheckKeys({"max_automata", "max_locations_per_automaton", "max_locations_total", "max_transitions",
                   "max_table_cells", "max_constraints", "max_string_bytes", "max_string_total"});
      num_in(b, "max_automata", c.budget.max_automata);
      num_in(b, "max_locations_per_automaton", c.budget.max_locations_per_automaton);
      num_in(b, "max_locations_total", c.budget.max_locations_total);
      num_in(b, "max_transitions", c.budget.max_transitions);
      num_in(b, "max_table_cells", c.budget.max_table_cells);
      num_in(b, "max_constraints", c.budget.max_constraints);
      num_in(b, "max_string_bytes", c.budget.max_string_bytes);
      num_in(b, "max_string_total", c.budget.max_string_total);
    }
    if (!d.ok()) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid config " + file, d);
  }
  if (const char* p = std::getenv("CTB_PORT"); p && *p) {
    char* end = nullptr;
    errno = 0;
    long v = std::strtol(p, &end, 10);
    if (errno != 0 || *end != '\0' || v < 0 || v > 65535)
      return Error{ErrorCode::kInvalidInput, "CTB_PORT must be a port number 0..65535", {}};
    c.port = static_cast<int>(v);
  }
  if (const char* h = std::getenv("CTB_HOST"); h && *h) c.host = h;
  if (const char* v = std::getenv("CTB_DATA_DIR"); v && *v) c.data_dir = v;
  if (const char* v = std::getenv("CTB_SESSION_STORE"); v && *v) c.session_store = v;
  if (const char* v = std::getenv("CTB_API_KEYS"); v && *v) c.api_keys_file = v;
  if (const char* v = std::getenv("CTB_GRPC_HOST"); v && *v) c.grpc_host = v;
  if (const char* v = std::getenv("CTB_MQTT_URL"); v && *v) c.mqtt_url = v;
  if (const char* v = std::getenv("CTB_MQTT_CLIENT_ID"); v && *v) c.mqtt_client_id = v;
  if (const char* p = std::getenv("CTB_GRPC_PORT"); p && *p) {
    char* end = nullptr;
    errno = 0;
    long v = std::strtol(p, &end, 10);
    if (errno != 0 || *end != '\0' || v < -1 || v > 65535)
      return Error{ErrorCode::kInvalidInput, "CTB_GRPC_PORT must be -1 (off) or a port 0..65535", {}};
    c.grpc_port = static_cast<int>(v);
  }
  if (const char* v = std::getenv("CTB_ALLOW_UNAUTHENTICATED"); v && std::string(v) == "1")
    c.allow_unauthenticated = true;
  auto llm = LlmConfig::FromEnv();
  if (auto* e = std::get_if<Error>(&llm)) return *e;
  c.llm = std::get<LlmConfig>(llm);
  return c;
}

std::optional<Error> ServerConfig::Validate() const {
  Diagnostics d;
  if (port < 0 || port > 65535) d.Error("/port", "port must be 0..65535");
  if (grpc_port < -1 || grpc_port > 65535) d.Error("/grpc_port", "must be -1 (off) or 0..65535");
  if (grpc_tls_cert.empty() != grpc_tls_key.empty())
    d.Error("/grpc_tls_cert", "give both grpc_tls_cert and grpc_tls_key, or neither");
  if (!mqtt_url.empty()) {
    auto parsed = mqtt::ParseMqttUrl(mqtt_url);
    if (auto* e = std::get_if<std::string>(&parsed)) d.Error("/mqtt_url", *e);
  }
  if (!mqtt_url.empty() && (mqtt_client_id.empty() || mqtt_client_id.size() > 184))
    d.Error("/mqtt_client_id", "must be 1..184 characters");
  if (max_grpc_streams_per_client < 1 || max_grpc_streams_per_client > 1024)
    d.Error("/max_grpc_streams_per_client", "must be 1..1024");
  auto range = [&](const char* ptr, long v, long lo, long hi) {
    if (v < lo || v > hi) d.Error(ptr, "must be " + std::to_string(lo) + ".." + std::to_string(hi));
  };
  range("/read_timeout_s", read_timeout_s, 1, 600);
  range("/body_timeout_s", body_timeout_s, 1, 3600);
  range("/keep_alive_s", keep_alive_s, 1, 600);
  range("/write_timeout_s", write_timeout_s, 1, 3600);
  range("/max_connections", max_connections, 4, 4096);
  range("/max_connections_per_address", max_connections_per_address, 1, max_connections);
  range("/solver_memory_mb", solver_memory_mb, 0, 1L << 20);
  if (solver_memory_mb != 0 && solver_memory_mb < 256) d.Error("/solver_memory_mb", "must be 0 (none) or >= 256");
  range("/max_horizon_limit", max_horizon_limit, 1, 1024);
  range("/max_sessions", max_sessions, 1, 10000000);
  range("/session_idle_s", session_idle_s, 1, 365L * 24 * 3600);
  range("/execution_lease_ms", execution_lease_ms, 300, 600000);
  range("/shutdown_grace_ms", shutdown_grace_ms, 0, 3600000);
  range("/budget/max_automata", budget.max_automata, 1, 64);
  range("/budget/max_locations_per_automaton", budget.max_locations_per_automaton, 1, 4096);
  range("/budget/max_locations_total", budget.max_locations_total, 1, 1L << 20);
  range("/budget/max_transitions", budget.max_transitions, 1, 1L << 22);
  range("/budget/max_table_cells", budget.max_table_cells, 1, 1L << 40);
  range("/budget/max_constraints", budget.max_constraints, 1, 1L << 16);
  range("/budget/max_string_bytes", budget.max_string_bytes, 16, 1L << 24);
  range("/budget/max_string_total", budget.max_string_total, 16, 1L << 30);
  if (max_body_bytes < 1024 || max_body_bytes > (64L << 20)) d.Error("/max_body_bytes", "must be 1 KiB..64 MiB");
  if (max_network_body_bytes < 1024 || max_network_body_bytes > (64L << 20))
    d.Error("/max_network_body_bytes", "must be 1 KiB..64 MiB");
  if (solver_workers < 1 || solver_workers > 64) d.Error("/solver_workers", "must be 1..64");
  if (solver_queue < 0 || solver_queue > 1024) d.Error("/solver_queue", "must be 0..1024");
  if (max_time_limit_ms < 100 || max_time_limit_ms > 3600000) d.Error("/max_time_limit_ms", "must be 100..3600000");
  if (default_time_limit_ms < 100 || default_time_limit_ms > max_time_limit_ms)
    d.Error("/default_time_limit_ms", "must be 100..max_time_limit_ms");
  if (!session_store.empty() && session_store != "sqlite" && session_store.rfind("redis://", 0) != 0)
    d.Error("/session_store", "must be \"sqlite\" or redis://host:port/db");
  if (session_store.empty() || session_store == "sqlite")
    if (data_dir.empty()) d.Error("/data_dir", "must name a directory");
  if (!std::filesystem::is_directory(config_dir + "/domains"))
    d.Error("/config_dir", "no domains/ folder in '" + config_dir + "'");
  if (d.ok()) return std::nullopt;
  return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid server configuration", d);
}

Json ServerConfig::ToLogJson() const {
  return {{"host", host}, {"port", port}, {"config_dir", config_dir}, {"static_dir", static_dir},
          {"max_body_bytes", max_body_bytes}, {"max_network_body_bytes", max_network_body_bytes},
          {"solver_workers", solver_workers},
          {"solver_queue", solver_queue}, {"default_time_limit_ms", default_time_limit_ms},
          {"max_time_limit_ms", max_time_limit_ms}, {"max_connections", max_connections},
          {"max_connections_per_address", max_connections_per_address},
          {"read_timeout_s", read_timeout_s}, {"solver_memory_mb", solver_memory_mb},
          {"budget", {{"max_automata", budget.max_automata},
                      {"max_locations_per_automaton", budget.max_locations_per_automaton},
                      {"max_locations_total", budget.max_locations_total},
                      {"max_transitions", budget.max_transitions},
                      {"max_table_cells", budget.max_table_cells},
                      {"max_constraints", budget.max_constraints},
                      {"max_string_bytes", budget.max_string_bytes},
                      {"max_string_total", budget.max_string_total}}},
          {"llm_base_url", llm.base_url},
          {"llm_model", llm.model}, {"llm_api_key", llm.MaskedKey()},
          {"session_store", session_store.empty() ? "sqlite:" + data_dir + "/sessions.db" : session_store},
          {"demo", demo}, {"grpc_port", grpc_port}, {"grpc_host", grpc_host},
          {"grpc_tls", !grpc_tls_cert.empty()}, {"api_keys", !api_keys_file.empty()},
          {"allow_unauthenticated", allow_unauthenticated},
          {"mqtt_url", mqtt_url}, {"mqtt_client_id", mqtt_client_id},
          {"llm_replay", !llm.replay_dir.empty() ? llm.replay_dir : demo ? recordings_dir + " (demo)" : ""}};
}

}  // namespace ctb::server
