// `ctburton serve`: one application core, the HTTP front end and (with a gRPC port) the gRPC
// front end in one process, sharing the core's job gate; signals handled on one thread.
#include "server/service.h"

#include <malloc.h>
#include <signal.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <mutex>
#include <thread>

#include "app/core.h"
#include "app/ids.h"
#include "grpc/grpc_front.h"
#include "mqtt/adapter.h"
#include "server/http_front.h"

namespace ctb::server {

namespace {

using Clock = std::chrono::steady_clock;

app::CoreConfig CoreConfigOf(const ServerConfig& c) {
  app::CoreConfig o;
  o.config_dir = c.config_dir;
  o.prompts_dir = c.prompts_dir;
  o.recordings_dir = c.recordings_dir;
  o.minizinc = c.minizinc;
  o.solver_memory_mb = c.solver_memory_mb;
  o.budget = c.budget;
  o.solver_workers = c.solver_workers;
  o.solver_queue = c.solver_queue;
  o.default_time_limit_ms = c.default_time_limit_ms;
  o.max_time_limit_ms = c.max_time_limit_ms;
  o.max_horizon_limit = c.max_horizon_limit;
  o.data_dir = c.data_dir;
  o.session_store = c.session_store;
  o.max_sessions = c.max_sessions;
  o.session_idle_s = c.session_idle_s;
  o.execution_lease_ms = c.execution_lease_ms;
  o.demo = c.demo;
  o.llm = c.llm;
  return o;
}

bool IsLoopback(const std::string& host) {
  return host == "127.0.0.1" || host == "::1" || host == "localhost" || host.rfind("127.", 0) == 0;
}

}  // namespace

// glibc's allocator keeps freed memory inside its arenas (one per busy thread, up to 8 per core):
// under a day's mixed load the server's resident size crept up while the memory in use stayed
// flat (bench/results/soak.md). Fewer arenas (4, unless MALLOC_ARENA_MAX says otherwise) and a
// malloc_trim every 30 s give that memory back.
class MemoryKeeper {
 public:
  MemoryKeeper() {
    if (!std::getenv("MALLOC_ARENA_MAX")) mallopt(M_ARENA_MAX, 4);
    thread_ = std::thread([this] {
      std::unique_lock<std::mutex> lock(mu_);
      while (!cv_.wait_for(lock, std::chrono::seconds(30), [this] { return stop_; })) malloc_trim(0);
    });
  }
  ~MemoryKeeper() {
    {
      std::lock_guard<std::mutex> lock(mu_);
      stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }

 private:
  std::mutex mu_;
  std::condition_variable cv_;
  bool stop_ = false;
  std::thread thread_;
};

int Serve(const ServerConfig& cfg) {
  // Signals: a dedicated thread waits for them (no work in a signal handler). Blocked first, so
  // that every thread started from here on (the MQTT adapter's, resumed executions') inherits
  // the mask and a SIGTERM drains instead of killing the process.
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGHUP);
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  MemoryKeeper memory;  // after the mask: its thread must not take a SIGTERM
  std::unique_ptr<app::ApiKeys> keys;
  if (!cfg.api_keys_file.empty()) {
    auto k = app::ApiKeys::Load(cfg.api_keys_file);
    if (auto* e = std::get_if<std::string>(&k)) {
      spdlog::error("{}", app::LogText(*e));
      return 2;
    }
    keys = std::move(std::get<std::unique_ptr<app::ApiKeys>>(k));
  } else if (!cfg.allow_unauthenticated &&
             (!IsLoopback(cfg.host) || (cfg.grpc_port >= 0 && !IsLoopback(cfg.grpc_host)))) {
    spdlog::error("{}", app::LogText("without --api-keys the server listens on loopback only; give "
                             "--api-keys FILE, or --allow-unauthenticated to serve " +
                             cfg.host + " without keys"));
    return 2;
  }
  // The MQTT adapter is registered with the core before it opens (executions resumed from the
  // store find it) and connected once the core is open.
  std::shared_ptr<mqtt::Adapter> mqtt_adapter;
  app::CoreConfig core_cfg = CoreConfigOf(cfg);
  if (!cfg.mqtt_url.empty()) {
    auto a = mqtt::Adapter::Create({cfg.mqtt_url, cfg.mqtt_client_id});
    if (auto* e = std::get_if<std::string>(&a)) {
      spdlog::error("{}", app::LogText(*e));
      return 2;
    }
    mqtt_adapter = std::get<std::shared_ptr<mqtt::Adapter>>(a);
    core_cfg.command_sinks["mqtt"] = mqtt_adapter;
  }
  auto opened = app::Core::Open(core_cfg);
  if (auto* e = std::get_if<Error>(&opened)) {
    spdlog::error("{}", app::LogText(e->message));
    return 2;
  }
  auto core = std::move(std::get<std::unique_ptr<app::Core>>(opened));
  // Declared after the core: stops the adapter's network thread (which calls into the core)
  // before the core is destroyed, on every return path.
  struct StopAdapter {
    std::shared_ptr<mqtt::Adapter> a;
    ~StopAdapter() {
      if (a) a->Stop();
    }
  } stop_adapter{mqtt_adapter};
  if (mqtt_adapter) {
    spdlog::info("{}", Json({{"event", "mqtt"}, {"url", cfg.mqtt_url}, {"client_id", cfg.mqtt_client_id},
                             {"commands", "ctburton/<execution>/<automaton>/command"},
                             {"reports", "ctburton/+/+/state"}}).dump());
    mqtt_adapter->Connect(*core);
  }
  HttpFrontEnd http(cfg, *core, keys.get());
  const int port = http.Bind();
  if (port < 0) {
    spdlog::error("{}", app::LogText("cannot listen on " + cfg.host + ":" + std::to_string(cfg.port)));
    return 2;
  }
  std::unique_ptr<grpcfront::GrpcFrontEnd> grpc;
  int grpc_port = -1;
  if (cfg.grpc_port >= 0) {
    grpcfront::GrpcOptions go{cfg.grpc_host, cfg.grpc_port, cfg.grpc_tls_cert, cfg.grpc_tls_key,
                              cfg.max_body_bytes, cfg.max_grpc_streams_per_client};
    auto g = grpcfront::GrpcFrontEnd::Start(go, *core, keys.get());
    if (auto* e = std::get_if<std::string>(&g)) {
      spdlog::error("{}", app::LogText(*e));
      return 2;
    }
    grpc = std::move(std::get<std::unique_ptr<grpcfront::GrpcFrontEnd>>(g));
    grpc_port = grpc->port();
  }
  Json listening = {{"event", "listening"}, {"host", cfg.host}, {"port", port},
                    {"config", cfg.ToLogJson()}};
  if (grpc) listening["grpc_port"] = grpc_port;
  if (mqtt_adapter) listening["mqtt_url"] = cfg.mqtt_url;
  spdlog::info("{}", listening.dump());
  std::atomic<bool> draining{false};
  std::thread signals([&] {
    for (;;) {
      int sig = 0;
      sigwait(&set, &sig);
      if (sig == SIGHUP) {
        if (!keys) continue;
        auto err = keys->Reload();
        spdlog::info("{}", Json({{"event", "api_keys_reloaded"}, {"ok", !err},
                                 {"keys", keys->size()}, {"error", err ? *err : ""}}).dump());
        continue;
      }
      spdlog::info("{}", Json({{"event", "draining"}, {"signal", sig}}).dump());
      draining = true;
      http.SetDraining();
      http.Stop();
      if (grpc) grpc->BeginShutdown();
      auto until = Clock::now() + std::chrono::milliseconds(cfg.shutdown_grace_ms);
      while ((http.InFlight() > 0 || (grpc && grpc->InFlight() > 0)) && Clock::now() < until)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      core->Shutdown();  // solver jobs stop; their processes are killed by the runner
      return;
    }
  });
  http.Listen();
  core->Shutdown();
  if (mqtt_adapter) mqtt_adapter->Stop();
  if (!draining) pthread_kill(signals.native_handle(), SIGTERM);  // the thread drains and ends
  signals.join();
  if (grpc) grpc->Wait();
  spdlog::info("{}", Json({{"event", "stopped"}}).dump());
  return 0;
}

}  // namespace ctb::server
