// The built-in simulated team (contract section 14, adapter "sim"): every automaton of a plan
// played as a device would, with faults injected on request. A commanded transition is reported
// done at the moment its command was sent (or, by chance, failed); a contingent one after a
// duration drawn in its bounds (or, by chance, late beyond them); any other transition when the
// plan's network lets it happen at the earliest, given what happened.
// Thread-compatible. Never throws (allocation aside).
#pragma once

#include <map>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "executive/run.h"
#include "planner/model/json_io.h"

namespace ctb::exec {

struct SimOptions {
  double fail = 0;     // the chance that a commanded move fails (reported `failed`)
  double late = 0;     // the chance that a contingent duration overruns its upper bound
  double late_by = 0;  // by how much (seconds); 0: the bounds' width plus one resolution step
  unsigned seed = 1;
  Json ToJson() const;
};

// Reads {"fail", "late", "late_by", "seed"} strictly; errors at prefix + "/<field>".
std::optional<SimOptions> ParseSimOptions(const Json& j, const std::string& prefix, Diagnostics& diags);

class SimTeam {
 public:
  SimTeam(SimOptions o, double resolution) : o_(o), res_(resolution), rng_(o.seed) {}

  // The reports due at or before `now` (plan seconds), in time order; each is given once.
  std::vector<Report> Due(const Run& run, double now);
  // When the next report falls due without a dispatch; nullopt when none is pending.
  std::optional<double> NextDue(const Run& run, double now);

 private:
  struct Pending {
    double at = 0;
    Report report;
  };
  std::vector<Pending> Pend(const Run& run);
  double Grid(double t) const;

  SimOptions o_;
  double res_;
  std::mt19937 rng_;
  std::map<std::string, Report> decided_;  // what each point's device will say, once drawn
  std::set<std::string> given_;
};

}  // namespace ctb::exec
