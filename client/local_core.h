// The CLI's local mode runs the same application core as the server (app/core.h): one core per
// process, sessions in memory, the planner's limits rather than a server's budget, and the LLM
// from the environment (CTB_LLM_*).
#pragma once

#include <memory>
#include <string>
#include <variant>

#include "app/core.h"

namespace ctb::cli {

// max_repairs >= 0 overrides the environment's (CTB_LLM_MAX_REPAIRS).
std::variant<std::unique_ptr<app::Core>, Error> OpenLocalCore(const std::string& config_dir,
                                                               bool with_llm, int max_repairs = -1);

// An error from the core about a file given on the command line: pointers relative to the file
// (the request's "/state_plan" prefix taken off).
Error RelativeTo(Error e, const std::string& prefix);
Diagnostic RelativeTo(Diagnostic d, const std::string& prefix);

// What `replan` and `execute` work on: the local core, the domain (a name under config_dir or a
// path) and the state plan file as JSON (checked by the core's calls). Its warnings were printed.
struct LocalProblem {
  std::unique_ptr<app::Core> core;
  app::DomainRef domain;
  Json state_plan;
};
std::variant<LocalProblem, Error> OpenLocalProblem(const std::string& domain, const std::string& config_dir,
                                                   const std::string& file);

// The state plan's warnings from the core's check (Core::Validate), one "warning: ..." line each
// on stderr with pointers relative to the file. Errors are left to the call that follows.
void PrintStatePlanWarnings(app::Core& core, const app::DomainRef& domain, const Json& state_plan);

}  // namespace ctb::cli
