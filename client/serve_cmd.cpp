#include <iostream>
#include <memory>
#include <string>

#include <spdlog/spdlog.h>

#include "client/commands.h"
#include "server/log_context.h"
#include "server/service.h"

namespace ctb::cli {

namespace {
struct ServeOptions {
  std::optional<int> port;
  std::string host, config_file, config_dir, data_dir, session_store;
  bool demo = false;
  std::optional<int> grpc_port;
  std::string grpc_host, grpc_tls_cert, grpc_tls_key, api_keys, mqtt_url, mqtt_client_id;
  bool allow_unauthenticated = false;
};

int RunServe(const ServeOptions& o) {
  spdlog::set_level(spdlog::level::info);
  // One JSON object per line: {"ts", "level", "request_id", "log": <the message>}.
  server::InstallJsonLogPattern();
  auto cfg = server::ServerConfig::Load(o.config_file);
  if (auto* e = std::get_if<Error>(&cfg)) {
    std::cerr << "error: " << e->ToString() << "\n";
    return 2;
  }
  auto& c = std::get<server::ServerConfig>(cfg);
  if (o.port) c.port = *o.port;
  if (!o.host.empty()) c.host = o.host;
  if (!o.config_dir.empty()) c.config_dir = o.config_dir;
  if (!o.data_dir.empty()) c.data_dir = o.data_dir;
  if (!o.session_store.empty()) c.session_store = o.session_store;
  if (o.demo) c.demo = true;
  if (o.grpc_port) c.grpc_port = *o.grpc_port;
  if (!o.grpc_host.empty()) c.grpc_host = o.grpc_host;
  if (!o.grpc_tls_cert.empty()) c.grpc_tls_cert = o.grpc_tls_cert;
  if (!o.grpc_tls_key.empty()) c.grpc_tls_key = o.grpc_tls_key;
  if (!o.api_keys.empty()) c.api_keys_file = o.api_keys;
  if (o.allow_unauthenticated) c.allow_unauthenticated = true;
  if (!o.mqtt_url.empty()) c.mqtt_url = o.mqtt_url;
  if (!o.mqtt_client_id.empty()) c.mqtt_client_id = o.mqtt_client_id;
  if (auto e = c.Validate()) {
    std::cerr << "error: " << e->ToString() << "\n";
    return 2;
  }
  return server::Serve(c);
}
}  // namespace

Runner AddServe(CLI::App& app) {
  auto o = std::make_shared<ServeOptions>();
  CLI::App* sub = app.add_subcommand("serve", "Run the HTTP service (default 127.0.0.1:8080), and gRPC with --grpc-port");
  sub->add_option("--port", o->port, "Port (0: any free port)")->check(CLI::Range(0, 65535));
  sub->add_option("--host", o->host, "Address to listen on (default 127.0.0.1)");
  sub->add_option("--config", o->config_file, "JSON configuration file");
  sub->add_option("--config-dir", o->config_dir, "Configuration directory (domains)");
  sub->add_option("--data-dir", o->data_dir, "Directory of the SQLite session store (default ./data)");
  sub->add_option("--session-store", o->session_store,
                  "Session store: sqlite (default) or redis://host:port/db (for several replicas)");
  sub->add_flag("--demo", o->demo,
                "Answer /plan and /translate from the shipped recordings when no LLM is configured");
  sub->add_option("--grpc-port", o->grpc_port, "Also serve gRPC on this port (0: any free port)")
      ->check(CLI::Range(0, 65535));
  sub->add_option("--grpc-host", o->grpc_host, "Address of the gRPC front end (default 127.0.0.1)");
  sub->add_option("--grpc-tls-cert", o->grpc_tls_cert, "PEM certificate chain for gRPC over TLS");
  sub->add_option("--grpc-tls-key", o->grpc_tls_key, "PEM private key for gRPC over TLS");
  sub->add_option("--api-keys", o->api_keys,
                  "File of API keys (one per line, or sha256:<hex>); every route but the health "
                  "checks then needs \"Authorization: Bearer KEY\"; re-read on SIGHUP");
  sub->add_flag("--allow-unauthenticated", o->allow_unauthenticated,
                "Serve a non-loopback address without --api-keys");
  sub->add_option("--mqtt-url", o->mqtt_url,
                  "MQTT broker for executions with adapter mqtt (mqtt://host[:port]; docs/executive.md)");
  sub->add_option("--mqtt-client-id", o->mqtt_client_id,
                  "MQTT client id: names the broker's persistent session (default ctburton)");
  return [o, sub]() { return sub->parsed() ? RunServe(*o) : -1; };
}

}  // namespace ctb::cli
