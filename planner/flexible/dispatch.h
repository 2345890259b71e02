// Executing a flexible plan against nature (contract section 13, `ctburton execute --sample`):
// contingent durations are drawn when their transition starts, and a dispatcher decides when the
// controllable transitions happen.
//   - dynamic: what has happened so far decides what starts next. At each moment, a point whose
//     turn has come is started when the network that remains (what happened fixed, what is still
//     running narrowed to what it can still take) stays dynamically controllable; otherwise it
//     waits. A dynamically controllable plan is never broken this way.
//   - fixed: every controllable transition at its planned time, whatever happened (how a
//     fixed-time schedule fares; its failures are what dynamic dispatch avoids).
// Time advances in whole domain ticks; reactions are instantaneous (Morris 2014's semantics).
// Thread-safe: plain functions over values.
#pragma once

#include <optional>
#include <random>
#include <string>
#include <vector>

#include "planner/flexible/flexible.h"
#include "planner/model/domain.h"

namespace ctb::flexible {

enum class Sampling { kUniform, kDistribution };  // distribution: the transition's, else uniform

struct DispatchOptions {
  bool dynamic = true;
  Sampling sampling = Sampling::kUniform;
};

struct Execution {
  std::vector<network::Ticks> times;  // realized time of every point (network ticks)
  bool met = false;                   // every link of the network holds
  std::string why;                    // the first link broken, or why the run stopped
};

// One execution of plan network `f` (derived from `plan` of domain `d`, contingent transitions
// marked there); `rng` draws nature's choices.
Execution Execute(const FlexiblePlan& f, const Domain& d, const std::vector<network::Ticks>& planned,
                  const DispatchOptions& o, std::mt19937& rng);

}  // namespace ctb::flexible
