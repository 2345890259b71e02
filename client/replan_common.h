// Shared by `ctburton replan` and `ctburton execute`: a domain and a state plan from files.
#pragma once

#include <string>
#include <utility>
#include <variant>

#include "planner/model/domain.h"
#include "planner/model/error.h"
#include "planner/model/state_plan.h"

namespace ctb::cli {

struct LoadedProblem {
  Domain domain;
  StatePlan sp;
};

// The domain (a name under config_dir, or a path) and the state plan file; an Error naming the
// file otherwise. Warnings go to stderr.
std::variant<LoadedProblem, Error> LoadProblem(const std::string& domain,
                                               const std::string& config_dir,
                                               const std::string& file);

}  // namespace ctb::cli
