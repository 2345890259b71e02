// The gRPC front end (contract section 10): service ctburton.v1.Planner over the application
// core, with the standard health service and server reflection. Every method but health needs
// "authorization: Bearer KEY" metadata when the server has API keys. A client's deadline or
// cancel stops its job (the core polls the call every 100 ms, so the solver is killed within a
// second). Streaming calls are capped per client address.
#pragma once

#include <memory>
#include <string>
#include <variant>

#include "app/api_keys.h"
#include "app/core.h"

namespace ctb::grpcfront {

struct GrpcOptions {
  std::string host = "127.0.0.1";
  int port = 0;                      // 0: any free port
  std::string tls_cert, tls_key;     // PEM files: TLS when both are given
  long max_message_bytes = 1 << 20;  // received messages beyond: RESOURCE_EXHAUSTED
  int max_streams_per_client = 8;
};

class GrpcFrontEnd {
 public:
  // Builds and starts the server; an error text when it cannot (port taken, unreadable PEM).
  // `core` and `keys` (may be null) must outlive it.
  static std::variant<std::unique_ptr<GrpcFrontEnd>, std::string> Start(const GrpcOptions& o,
                                                                        app::Core& core,
                                                                        const app::ApiKeys* keys);
  ~GrpcFrontEnd();
  int port() const;
  int InFlight() const;
  // Stops accepting calls; running ones get until the core cancels them. Returns at once.
  void BeginShutdown();
  // Waits until the server has stopped (calls BeginShutdown() if nobody did).
  void Wait();

 private:
  struct Impl;
  explicit GrpcFrontEnd(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace ctb::grpcfront
