// The service's configuration: one struct, filled once from defaults, an optional JSON file,
// the environment and flags (later wins), validated at start and logged with the key masked.
#pragma once

#include <string>
#include <variant>

#include "planner/model/error.h"
#include "planner/model/json_io.h"
#include "app/budget.h"
#include "translator/llm.h"

namespace ctb::server {

struct ServerConfig {
  std::string host = "127.0.0.1";
  int port = 8080;
  std::string config_dir;   // domains: <config_dir>/domains/*.json
  std::string prompts_dir;
  std::string static_dir;   // the web page
  std::string minizinc = "minizinc";
  std::string recordings_dir;      // answers /plan and /translate when no LLM is configured
  long max_body_bytes = 1 << 20;   // 413 beyond
  long max_network_body_bytes = 4 << 20;  // POST /networks/check only (10,000 points fit)
  int read_timeout_s = 5;          // a request head must arrive within this (slow clients: 408)
  int body_timeout_s = 10;         // and its body within this after the head
  int keep_alive_s = 5;            // an idle keep-alive connection is closed after this
  int write_timeout_s = 60;
  int max_connections = 128;       // at once; beyond: 503 at once (the pool has 16 threads more)
  int max_connections_per_address = 32;
  long solver_memory_mb = 2048;    // RLIMIT_AS of each solver process (0: none)
  app::ModelBudget budget;              // the model-size budget of one request (server/budget.h)
  int solver_workers = 2;          // solves at once
  int solver_queue = 8;            // solves waiting; beyond: 503 with Retry-After
  long default_time_limit_ms = 30000;
  long max_time_limit_ms = 60000;  // a request's time_limit_ms is capped to this
  int max_horizon_limit = 64;
  std::string data_dir = "./data";  // the SQLite session store (sessions.db)
  std::string session_store;        // "" / "sqlite", or "redis://host:port/db"
  bool demo = false;                // answer /plan and /translate from recordings_dir without an LLM
  int max_sessions = 1000;
  int session_idle_s = 1800;
  // How long a replica's claim on an execution lasts without renewal (shared Redis store: another
  // replica takes over an execution whose claim has run out).
  long execution_lease_ms = 3000;
  int shutdown_grace_ms = 5000;    // in-flight work gets this long, then is cancelled
  // gRPC front end (contract section 10): off when grpc_port < 0; 0 picks a free port.
  int grpc_port = -1;
  std::string grpc_host = "127.0.0.1";
  std::string grpc_tls_cert, grpc_tls_key;  // PEM files; both or neither
  int max_grpc_streams_per_client = 8;      // streaming calls at once from one peer address
  // Access control for both front ends: a file of keys (app/api_keys.h); "" = none, and then
  // only loopback addresses are served unless allow_unauthenticated.
  std::string api_keys_file;
  bool allow_unauthenticated = false;
  // The executive's MQTT adapter (contract section 14; mqtt/adapter.h): "" = off, else
  // mqtt://host[:port]; the client id names the broker's persistent session (keep it stable, and
  // give each replica its own).
  std::string mqtt_url;
  std::string mqtt_client_id = "ctburton";
  LlmConfig llm;

  // Defaults, then the file (if any), then the environment (CTB_*), as documented in
  // docs/service.md. Flags are applied by the caller before Validate().
  static std::variant<ServerConfig, Error> Load(const std::string& file);
  std::optional<Error> Validate() const;
  Json ToLogJson() const;  // the key masked
};

}  // namespace ctb::server
