// The HTTP front end (contract section 6): cpp-httplib routes over the application core. It
// parses bodies, turns them into the core's typed calls, and the results and errors into JSON;
// nothing of a use case is decided here. Streaming (server/stream.h) hands the core an observer;
// a client whose connection is gone cancels its job. With API keys, every route but /healthz
// and /readyz (and the static page) needs "Authorization: Bearer KEY".
#pragma once

#include <atomic>
#include <memory>

#include "app/api_keys.h"
#include "app/core.h"
#include "server/config.h"

namespace ctb::server {

class HttpFrontEnd {
 public:
  // `keys` may be null (no access control). Both must outlive the front end.
  HttpFrontEnd(const ServerConfig& cfg, app::Core& core, const app::ApiKeys* keys);
  ~HttpFrontEnd();
  // Binds the configured address; the bound port, or -1.
  int Bind();
  // Serves until Stop(); blocks.
  void Listen();
  // Stops accepting; in-flight requests finish (or are cancelled by the core's Shutdown()).
  void Stop();
  // Requests being handled, for the shutdown drain.
  int InFlight() const;
  // Makes /readyz answer 503 (the server is draining).
  void SetDraining();

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ctb::server
