// The CLI's local mode runs the same application core as the server (app/core.h): one core per
// process, sessions in memory, the planner's limits rather than a server's budget, and the LLM
// from the environment (CTB_LLM_*).
#pragma once

#include <memory>
#include <string>
#include <variant>

#include "app/core.h"

namespace ctb::cli {

std::variant<std::unique_ptr<app::Core>, Error> OpenLocalCore(const std::string& config_dir,
                                                               bool with_llm);

// An error from the core about a file given on the command line: pointers relative to the file
// (the request's "/state_plan" prefix taken off).
Error RelativeTo(Error e, const std::string& prefix);

}  // namespace ctb::cli
