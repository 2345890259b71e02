// The HTTP service (contract section 6): thin routes over the planner and translator libraries.
#pragma once

#include "server/config.h"

namespace ctb::server {

// Runs until SIGTERM/SIGINT: stops accepting, lets in-flight work finish within
// shutdown_grace_ms, then cancels solver jobs (their processes are killed) and returns 0.
// Returns non-zero when the server cannot start.
int Serve(const ServerConfig& cfg);

}  // namespace ctb::server
