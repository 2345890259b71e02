// The request id of the request being handled on this thread, printed by the log pattern's %* flag
// in every log line (the planner's included). Set by the service around each handler.
#pragma once

#include <string>

namespace ctb::server {

void SetThreadRequestId(const std::string& id);
const std::string& ThreadRequestId();

// Installs the JSON-lines log pattern: {"ts", "level", "request_id", "log": <message>}.
void InstallJsonLogPattern();

}  // namespace ctb::server
