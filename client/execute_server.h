// `ctburton execute --server URL`: the execution runs in a server (contract section 14,
// POST /executions on its simulated team), and this command follows it: each event (commands
// sent, reports, replans, the end) printed as it comes, as text or one JSON object a line.
#pragma once

#include <string>

namespace ctb::cli {

struct ServerExecuteOptions {
  std::string server, domain, file, objective;
  double speed = 1;
  double fail = 0;
  unsigned seed = 1;
  bool json = false;
  long time_limit_ms = 60000;
};

// 0 when the execution succeeded, 1 when it failed or was stopped, 2 for a bad request, 3 when
// the server could not be reached or followed.
int RunServerExecute(const ServerExecuteOptions& o);

}  // namespace ctb::cli
