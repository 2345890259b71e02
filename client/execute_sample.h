// `ctburton execute --sample`: simulated executions of a flexible plan against nature (contract
// section 13): N runs with contingent durations drawn from their bounds or distributions, each
// dispatched dynamically (or at the plan's fixed times), each realized trajectory checked by the
// section-5 verifier.
#pragma once

#include <string>

namespace ctb::cli {

struct SampleOptions {
  std::string domain, file, config_dir, objective, controllability;
  std::string sample = "uniform";     // uniform | distribution
  std::string dispatch = "dynamic";   // dynamic | fixed
  unsigned seed = 1;
  int runs = 1;
  bool json = false;
  long time_limit_ms = 60000;
};

// Prints {"runs", "succeeded", "violated"} last (after one trajectory a line with --json).
// Exit 0 when every run succeeded, 5 when some were violated, 1/3 on bad input or no plan.
int RunSampledExecutions(const SampleOptions& o);

}  // namespace ctb::cli
